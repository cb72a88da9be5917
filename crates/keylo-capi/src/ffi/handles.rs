//! Pipeline handles: a `KeyloPipeline *` is a number the table maps to a live pipeline, never
//! dereferenced, so a freed, twice-freed or made-up handle is refused instead of being
//! undefined behaviour; numbers are never reused.

use std::collections::BTreeMap;
use std::ffi::CString;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError, TryLockError};

use super::types::{KeyloPipeline, KEYLO_CAPI_BUSY, KEYLO_CAPI_ERROR, KEYLO_CAPI_OK};
use crate::{CapiError, Embedded};

/// One pipeline and the text of its last error.
pub(crate) struct State {
    /// `None` after a panic inside a call (the pipeline is poisoned).
    pub inner: Option<Embedded>,
    pub error: CString,
}

type Slot = Arc<Mutex<State>>;

struct Table {
    next: usize,
    live: BTreeMap<usize, Slot>,
}

static TABLE: Mutex<Table> = Mutex::new(Table {
    next: 1,
    live: BTreeMap::new(),
});

/// Handles step by this much: small integers (and NULL) are never handles.
const STRIDE: usize = 16;

fn table() -> MutexGuard<'static, Table> {
    // The table is only changed by short, panic-free code; a poisoned lock is still sound.
    TABLE.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Registers a new pipeline; its handle.
pub(crate) fn insert(inner: Embedded) -> *mut KeyloPipeline {
    let slot = Arc::new(Mutex::new(State {
        inner: Some(inner),
        error: CString::default(),
    }));
    let mut t = table();
    let id = t.next;
    t.next += 1;
    t.live.insert(id, slot);
    std::ptr::without_provenance_mut(id * STRIDE)
}

/// The table key of handle `p` (`None` for NULL and values keylo never hands out).
fn id_of(p: *const KeyloPipeline) -> Option<usize> {
    let addr = p.addr();
    (addr != 0 && addr.is_multiple_of(STRIDE)).then_some(addr / STRIDE)
}

/// The pipeline of handle `p`, if it is live.
pub(crate) fn lookup(p: *const KeyloPipeline) -> Option<Slot> {
    table().live.get(&id_of(p)?).cloned()
}

/// Removes handle `p` (a no-op for one that is not live) and waits for a call running on it
/// in another thread.
pub(crate) fn remove(p: *mut KeyloPipeline) {
    let Some(id) = id_of(p) else {
        return;
    };
    let slot = table().live.remove(&id);
    if let Some(slot) = slot {
        drop(slot.lock().unwrap_or_else(PoisonError::into_inner));
    }
}

/// Why a handle is refused (the text `keylo_pipeline_error` gives for it).
pub(crate) fn refusal(p: *const KeyloPipeline) -> &'static std::ffi::CStr {
    if p.is_null() {
        c"pipeline is NULL"
    } else {
        c"not a live keylo pipeline (already freed, or not from keylo_pipeline_new)"
    }
}

pub(crate) fn panic_text(p: Box<dyn std::any::Any + Send>) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_default()
}

/// Runs `f` on the pipeline (catching panics), recording its error: `KEYLO_CAPI_OK`,
/// `KEYLO_CAPI_ERROR`, or `KEYLO_CAPI_BUSY` when another thread is inside a call on it.
pub(crate) fn with(
    p: *mut KeyloPipeline,
    f: impl FnOnce(&mut Embedded) -> Result<(), CapiError>,
) -> i32 {
    let Some(slot) = lookup(p) else {
        return KEYLO_CAPI_ERROR;
    };
    let mut state = match slot.try_lock() {
        Ok(s) => s,
        Err(TryLockError::WouldBlock) => return KEYLO_CAPI_BUSY,
        Err(TryLockError::Poisoned(e)) => e.into_inner(),
    };
    let State { inner, error } = &mut *state;
    let outcome = match inner.as_mut() {
        None => Err(CapiError::Argument(
            "the pipeline failed earlier (a panic); free it".into(),
        )),
        Some(e) => match catch_unwind(AssertUnwindSafe(|| f(e))) {
            Ok(r) => r,
            Err(panic) => {
                *inner = None;
                Err(CapiError::Panic(panic_text(panic)))
            }
        },
    };
    match outcome {
        Ok(()) => {
            *error = CString::default();
            KEYLO_CAPI_OK
        }
        Err(e) => {
            *error = to_cstring(&e.to_string());
            KEYLO_CAPI_ERROR
        }
    }
}

/// `s` as a C string (inner NULs become spaces).
pub(crate) fn to_cstring(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).unwrap_or_default()
}
