//! ONNX Runtime sessions for the learned detectors (`superpoint`, `xfeat`): built on the
//! process's ONNX Runtime ([`crate::superpoint::runtime`]) with the same options, and shared by
//! every stage instance with the same model and settings.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

use ort::session::builder::{GraphOptimizationLevel, SessionBuilder};
use ort::session::Session;

use crate::superpoint::runtime;
use crate::FeaturesError;

static SESSIONS: Mutex<BTreeMap<String, Arc<Mutex<Session>>>> = Mutex::new(BTreeMap::new());

/// The session under `key` (model and settings), made by `build` the first time.
pub(crate) fn shared(
    key: String,
    build: impl FnOnce() -> Result<Session, FeaturesError>,
) -> Result<Arc<Mutex<Session>>, FeaturesError> {
    let mut sessions = SESSIONS.lock().unwrap_or_else(|p| p.into_inner());
    if let Some(session) = sessions.get(&key) {
        return Ok(session.clone());
    }
    let session = Arc::new(Mutex::new(build()?));
    sessions.insert(key, session.clone());
    Ok(session)
}

/// A builder on the ONNX Runtime library `onnxruntime` (a config path, may be empty): every
/// graph optimisation, `threads` intra-op threads (0: ONNX Runtime's choice), worker threads
/// spinning or not; errors start with `what` (e.g. "SuperPoint model `built-in`").
pub(crate) fn builder(
    onnxruntime: &str,
    threads: usize,
    spinning: bool,
    what: &str,
) -> Result<SessionBuilder, FeaturesError> {
    let environment = runtime::environment(onnxruntime)?;
    let fail = |e: String| FeaturesError::Unavailable(format!("{what}: {e}"));
    let mut builder = Session::builder(environment)
        .map_err(|e| fail(e.to_string()))?
        .with_optimization_level(GraphOptimizationLevel::All)
        .map_err(|e| fail(e.to_string()))?
        .with_intra_op_spinning(spinning)
        .map_err(|e| fail(e.to_string()))?;
    if threads > 0 {
        builder = builder
            .with_intra_threads(threads)
            .map_err(|e| fail(e.to_string()))?;
    }
    Ok(builder)
}
