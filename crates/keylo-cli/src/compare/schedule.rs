//! Running each planned configuration as its own `keylo run` child process, N at a time,
//! skipping runs whose folder already holds a finished `summary.json`.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use super::child;
use super::error::CompareError;

/// One run to do: what `keylo run` gets and where it writes.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Planned {
    /// `data-label/variant`, unique; also the run folder under `<out>/runs/`.
    pub id: String,
    /// Label of the data (a column of the paper-shaped tables).
    pub data_label: String,
    /// Label of the configuration (a row of the paper-shaped tables).
    pub variant: String,
    pub config: Option<PathBuf>,
    pub data: PathBuf,
    pub gt: Option<PathBuf>,
    /// `--gt-time-scale` / `--gt-time-offset` of the ground truth (`None`: its times as read).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gt_time: Option<keylo::eval::stamp_map::StampMap>,
    /// The ground truth's name in tables and plots (`--gt-label`, else its file name).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gt_label: Option<String>,
    /// `--set` strings: the user's, then the grid point's.
    pub sets: Vec<String>,
    /// `--realtime` speed of the run (`None`: as fast as it goes).
    pub realtime: Option<f64>,
    /// `--images N` of the run (pictures only: not part of what resume compares).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub images: Option<u64>,
    /// The run folder (`<out>/runs/<id>`; not part of a shard's study, whose shards write
    /// to folders of their own).
    #[serde(skip)]
    pub dir: PathBuf,
    /// Expected cost relative to other runs (data bytes × a factor for the heavier stages),
    /// for balancing shards.
    #[serde(skip)]
    pub cost: f64,
}

/// How a run ended, as the scheduler saw it.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct Outcome {
    /// The run was not started: its folder already had a finished summary.json.
    pub resumed: bool,
    /// The run reached `--timeout` and was stopped.
    pub timed_out: bool,
    /// Exit status of `keylo run` (`None`: killed by a signal, or resumed).
    pub exit_code: Option<i32>,
    /// Seconds the child ran.
    pub seconds: f64,
    /// The last line of the child's stderr when it failed.
    pub error: Option<String>,
}

/// The file in a run folder that records what the run was asked to do.
const PLAN_FILE: &str = "compare-plan.json";

/// What a run was asked: config, data, ground truth and overrides (resume compares these).
fn plan_text(plan: &Planned) -> String {
    let mut v = serde_json::json!({
        "config": plan.config.as_ref().map(|p| p.display().to_string()),
        "data": plan.data.display().to_string(),
        "gt": plan.gt.as_ref().map(|p| p.display().to_string()),
        "sets": plan.sets,
    });
    // Only a paced run records its speed, so the plans of earlier runs still match.
    if let (Some(speed), Some(map)) = (plan.realtime, v.as_object_mut()) {
        map.insert("realtime".into(), serde_json::json!(speed));
    }
    // Likewise a ground truth with a time map (it changes the run's accuracy figures).
    if let (Some(time), Some(map)) = (plan.gt_time, v.as_object_mut()) {
        map.insert("gt_time".into(), serde_json::json!(time));
    }
    serde_json::to_string_pretty(&v).unwrap_or_default()
}

/// Whether a finished run may be reused: its recorded plan (when it has one) is this plan.
fn same_plan(plan: &Planned) -> bool {
    match std::fs::read_to_string(plan.dir.join(PLAN_FILE)) {
        Ok(text) => text == plan_text(plan),
        Err(_) => true,
    }
}

/// True when `dir/summary.json` is a finished summary (written last by `keylo run`) of a run
/// that was not interrupted (a run stopped by `--timeout` or Ctrl-C is run again on resume).
pub fn is_done(dir: &Path) -> bool {
    std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .is_some_and(|v| {
            let interrupted = v["failed"]["error"]
                .as_str()
                .is_some_and(|e| e.starts_with("interrupted"));
            v.get("frames").is_some() && !interrupted
        })
}

/// How the runs are done.
#[derive(Debug, Clone)]
pub struct Options {
    /// Runs at a time.
    pub jobs: usize,
    /// `--threads` for each run.
    pub threads: Option<usize>,
    /// `--trust-plugins` for each run.
    pub trust_plugins: bool,
    /// Run again even where a finished summary is found.
    pub rerun: bool,
    /// Stop a run that takes longer than this.
    pub timeout: Option<Duration>,
    /// No progress lines.
    pub quiet: bool,
}

/// Runs every plan (`jobs` at a time) and returns their outcomes in plan order.
pub fn run_all(plans: &[Planned], opts: &Options) -> Result<Vec<Outcome>, CompareError> {
    let exe = std::env::current_exe().map_err(|e| CompareError::Spawn {
        run: "every run".into(),
        source: e,
    })?;
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Result<Outcome, CompareError>>>> =
        Mutex::new(plans.iter().map(|_| None).collect());
    std::thread::scope(|s| {
        for _ in 0..opts.jobs.clamp(1, plans.len().max(1)) {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                let Some(plan) = plans.get(i) else { break };
                let r = run_one(&exe, plan, opts);
                let n = done.fetch_add(1, Ordering::SeqCst) + 1;
                if !opts.quiet {
                    eprintln!("[{n}/{}] {}: {}", plans.len(), plan.id, describe(&r));
                }
                if let Ok(mut v) = results.lock() {
                    v[i] = Some(r);
                }
            });
        }
    });
    let results = results.into_inner().unwrap_or_default();
    results
        .into_iter()
        .map(|r| r.unwrap_or_else(|| Ok(Outcome::default())))
        .collect()
}

fn describe(r: &Result<Outcome, CompareError>) -> String {
    match r {
        Err(e) => format!("error: {e}"),
        Ok(o) if o.resumed => "skipped: summary.json of an earlier run is there \
                               (resumed; --rerun runs it again)"
            .into(),
        Ok(o) if o.timed_out => format!(
            "timed out after {:.1} s: stopped ({})",
            o.seconds,
            o.error.as_deref().unwrap_or("no message")
        ),
        Ok(o) => match (o.exit_code, &o.error) {
            (Some(0), _) => format!("done in {:.1} s", o.seconds),
            (code, err) => format!(
                "failed ({}) after {:.1} s: {}",
                code.map_or("killed by a signal".into(), |c| format!("exit status {c}")),
                o.seconds,
                err.as_deref().unwrap_or("no message")
            ),
        },
    }
}

fn run_one(exe: &Path, plan: &Planned, opts: &Options) -> Result<Outcome, CompareError> {
    let (threads, rerun) = (opts.threads, opts.rerun);
    let done = is_done(&plan.dir);
    if !rerun && done && same_plan(plan) {
        return Ok(Outcome {
            resumed: true,
            ..Outcome::default()
        });
    }
    if done && !rerun {
        eprintln!(
            "note: {}: its folder holds a finished run of other settings ({PLAN_FILE}); running it again",
            plan.id
        );
    }
    std::fs::create_dir_all(&plan.dir).map_err(|e| CompareError::io(&plan.dir, e))?;
    let plan_path = plan.dir.join(PLAN_FILE);
    std::fs::write(&plan_path, plan_text(plan)).map_err(|e| CompareError::io(&plan_path, e))?;
    // A summary left by an earlier, unfinished attempt must not count as this run's.
    let _ = std::fs::remove_file(plan.dir.join("summary.json"));
    let mut cmd = Command::new(exe);
    cmd.arg("run");
    if let Some(c) = &plan.config {
        cmd.arg(c);
    }
    cmd.arg("--data")
        .arg(&plan.data)
        .arg("--out")
        .arg(&plan.dir);
    if let Some(gt) = &plan.gt {
        cmd.arg("--gt").arg(gt);
    }
    if let (Some(_), Some(label)) = (&plan.gt, &plan.gt_label) {
        cmd.arg(format!("--gt-label={label}"));
    }
    if let Some(time) = plan.gt_time {
        cmd.arg(format!("--gt-time-scale={}", time.scale))
            .arg(format!("--gt-time-offset={}", time.offset_s));
    }
    if let Some(t) = threads {
        cmd.arg("--threads").arg(t.to_string());
    }
    for s in &plan.sets {
        cmd.arg("--set").arg(s);
    }
    if opts.trust_plugins {
        cmd.arg("--trust-plugins");
    }
    if let Some(speed) = plan.realtime {
        cmd.arg(format!("--realtime={speed}"));
    }
    if let Some(every) = plan.images {
        cmd.arg(format!("--images={every}"));
    }
    let log = |name: &str| {
        let p = plan.dir.join(name);
        std::fs::File::create(&p).map_err(|e| CompareError::io(&p, e))
    };
    cmd.arg("-q")
        .stdin(Stdio::null())
        .stdout(log("stdout.log")?)
        .stderr(log("stderr.log")?);
    let start = Instant::now();
    let spawn_error = |e| CompareError::Spawn {
        run: plan.id.clone(),
        source: e,
    };
    let mut child = cmd.spawn().map_err(spawn_error)?;
    let ended = child::wait(&mut child, opts.timeout).map_err(spawn_error)?;
    let seconds = start.elapsed().as_secs_f64();
    let error = (ended.timed_out || !ended.status.success())
        .then(|| last_line(&plan.dir.join("stderr.log")));
    Ok(Outcome {
        resumed: false,
        timed_out: ended.timed_out,
        exit_code: ended.status.code(),
        seconds,
        error,
    })
}

/// The error line of a failed run's stderr: its first `error…` or panic line, else its last line.
fn last_line(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let lines = || text.lines().map(str::trim).filter(|l| !l.is_empty());
    lines()
        .find(|l| l.starts_with("error") || l.contains("panicked"))
        .or_else(|| lines().next_back())
        .unwrap_or("no message on stderr")
        .to_string()
}
