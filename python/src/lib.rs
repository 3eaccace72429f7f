//! `strider._strider`, the native half of the `strider` Python package: runs that return what
//! `strider run --format json` prints, a steppable simulation whose state reads as NumPy arrays,
//! fuzzy engines evaluated over whole arrays, and the animation controller's MDP.
//!
//! Everything here goes through the library's own front doors (`cli::run::PreparedRun`, the
//! loading layer, `cli::merge`), so Python sees exactly what the command line sees. Input
//! errors become `strider.StriderError` (a `ValueError`) carrying strider's `file:line:col`
//! message; long calls release the GIL and stop on Ctrl-C.

mod anim;
mod fuzzy;
mod simulation;

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use pyo3::{IntoPyObjectExt, create_exception};

use strider::cli::merge;
use strider::cli::run::{DataFormat, MapArgs, OptimumArg, PreparedRun, RunArgs, RunIdentity, thread_pool};
use strider::experiment::{self, Shard};
use strider::load::{BodyArgs, BodyKind, Failure};

create_exception!(
    _strider,
    StriderError,
    PyValueError,
    "A bad input to strider (a missing file, a bad map, script or FLL text, a bad argument); the message names file, line and column as the command line does."
);

/// The Python exception for a failed input: its message is what `strider` prints after
/// `error:`, and `file`, `line`, `col` are set when the error points into a source text.
pub(crate) fn input_error(py: Python<'_>, failure: Failure) -> PyErr {
    let e = match failure {
        Failure::Input(e) | Failure::Task(e) => e,
    };
    let err = StriderError::new_err(format!("{e:#}"));
    if let Some(src) = e.downcast_ref::<strider::diagnostic::SourceError>() {
        let value = err.value(py);
        let _ = value.setattr("file", src.file.as_str());
        let _ = value.setattr("line", src.line);
        let _ = value.setattr("col", src.col);
    }
    err
}

/// [`input_error`] for errors that are not yet a [`Failure`].
pub(crate) fn error<E: Into<Failure>>(py: Python<'_>) -> impl FnOnce(E) -> PyErr + '_ {
    move |e| input_error(py, e.into())
}

/// Runs `work` on a thread of its own with the GIL released, checking for Ctrl-C at least
/// every 20 ms:
/// on an interrupt `stop` is set, `work` is waited for (it should return soon after) and the
/// `KeyboardInterrupt` is raised.
pub(crate) fn interruptible<T: Send>(
    py: Python<'_>,
    stop: &AtomicBool,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    let done = AtomicBool::new(false);
    std::thread::scope(|s| {
        let handle = s.spawn(|| {
            let out = work();
            done.store(true, Ordering::Release);
            out
        });
        let mut interrupt = None;
        // Short work returns at once; long work is polled every 20 ms at most.
        let mut nap = Duration::from_micros(50);
        while !done.load(Ordering::Acquire) {
            py.detach(|| std::thread::sleep(nap));
            nap = (nap * 2).min(Duration::from_millis(20));
            if interrupt.is_none()
                && let Err(e) = py.check_signals()
            {
                stop.store(true, Ordering::Release);
                interrupt = Some(e);
            }
        }
        let out = py.detach(|| handle.join()).map_err(|_| PyRuntimeError::new_err("strider panicked"))?;
        match interrupt {
            Some(e) => Err(e),
            None => Ok(out),
        }
    })
}

/// A body name from Python: `"animated"` or `"disc"`.
pub(crate) fn body_kind(body: &str) -> PyResult<BodyKind> {
    match body {
        "animated" => Ok(BodyKind::Animated),
        "disc" => Ok(BodyKind::Disc),
        other => Err(StriderError::new_err(format!("body must be 'animated' or 'disc', found '{other}'"))),
    }
}

/// The command line's arguments of a run from Python's.
#[allow(clippy::too_many_arguments)]
pub(crate) fn run_args(
    map: &str,
    episodes: Option<usize>,
    body: &str,
    seed: u64,
    rules: Option<PathBuf>,
    scen: Option<PathBuf>,
    threads: Option<usize>,
    shard: Option<(usize, usize)>,
) -> PyResult<RunArgs> {
    let shard = shard.map(|(i, n)| Shard::new(i, n)).transpose().map_err(StriderError::new_err)?;
    Ok(RunArgs {
        map: MapArgs { map: map.to_string(), scen, rules, seed },
        episodes,
        format: DataFormat::Json,
        threads,
        body: BodyArgs { body: body_kind(body)?, ..BodyArgs::default() },
        bvh_out: None,
        shard,
        optimum: OptimumArg::On,
    })
}

/// A JSON value as the Python object `json.loads` makes of it (numbers keep every bit).
pub(crate) fn to_python<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    use serde_json::Value;
    Ok(match value {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => b.into_bound_py_any(py)?,
        Value::Number(n) => match (n.as_u64(), n.as_i64(), n.as_f64()) {
            (Some(u), _, _) => u.into_bound_py_any(py)?,
            (None, Some(i), _) => i.into_bound_py_any(py)?,
            (None, None, Some(f)) => f.into_bound_py_any(py)?,
            _ => return Err(PyRuntimeError::new_err(format!("cannot convert the number {n}"))),
        },
        Value::String(s) => s.into_bound_py_any(py)?,
        Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(to_python(py, item)?)?;
            }
            list.into_any()
        }
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (k, v) in map {
                dict.set_item(k, to_python(py, v)?)?;
            }
            dict.into_any()
        }
    })
}

/// The object `strider run --format json` prints for `records` (of a shard of the run
/// `identity`, or of a whole run).
fn run_document(identity: Option<&RunIdentity>, records: &[experiment::EpisodeRecord]) -> PyResult<serde_json::Value> {
    let mut text = Vec::new();
    strider::cli::run::write_records(&mut text, DataFormat::Json, identity, &experiment::summarize(records), records)
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    serde_json::from_slice(&text).map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// Runs navigation episodes: `strider run MAP --format json` as a dict.
#[pyfunction]
#[pyo3(signature = (map, *, episodes=None, body="animated", seed=1, rules=None, scen=None, threads=None, shard=None))]
#[allow(clippy::too_many_arguments)]
fn run(
    py: Python<'_>,
    map: PathBuf,
    episodes: Option<usize>,
    body: &str,
    seed: u64,
    rules: Option<PathBuf>,
    scen: Option<PathBuf>,
    threads: Option<usize>,
    shard: Option<(usize, usize)>,
) -> PyResult<Py<PyAny>> {
    let args = run_args(&map.to_string_lossy(), episodes, body, seed, rules, scen, threads, shard)?;
    let prepared = py.detach(|| PreparedRun::new(&args)).map_err(error(py))?;
    let pool = thread_pool(args.threads).map_err(error(py))?;
    // Episodes go in waves of a few per thread, so that Ctrl-C stops the run within a wave.
    let wave = 4 * pool.current_num_threads().max(1);
    let stop = AtomicBool::new(false);
    let records = interruptible(py, &stop, || {
        let mut records = Vec::with_capacity(prepared.episodes.len());
        for chunk in prepared.episodes.chunks(wave) {
            if stop.load(Ordering::Acquire) {
                break;
            }
            records.extend(pool.install(|| prepared.run(chunk, &|_| {}, &|_| {})));
        }
        records
    })?;
    Ok(to_python(py, &run_document(prepared.identity.as_ref(), &records)?)?.unbind())
}

/// Joins the JSON texts a run's shards printed into what the whole run prints.
#[pyfunction]
fn merge_json(py: Python<'_>, outputs: Vec<String>) -> PyResult<Py<PyAny>> {
    let parts: Vec<(String, String)> =
        outputs.into_iter().enumerate().map(|(i, t)| (format!("<shard output {i}>"), t)).collect();
    let merged = py.detach(|| merge::merge(&parts)).map_err(error(py))?;
    let merge::MergedRun::Json(records) = merged else {
        return Err(StriderError::new_err("expected the JSON outputs of strider run"));
    };
    Ok(to_python(py, &run_document(None, &records)?)?.unbind())
}

/// The episodes of a run of `map` (one per task, or one for random worlds, unless `episodes`).
#[pyfunction]
#[pyo3(signature = (map, *, episodes=None, scen=None))]
fn episode_count(py: Python<'_>, map: PathBuf, episodes: Option<usize>, scen: Option<PathBuf>) -> PyResult<usize> {
    let args = MapArgs { map: map.to_string_lossy().into_owned(), scen, rules: None, seed: 1 };
    let source = py.detach(|| strider::cli::run::load_map_args(&args)).map_err(error(py))?;
    let n = strider::load::episode_count(&source, episodes);
    strider::cli::run::check_episodes(n).map_err(error(py))?;
    Ok(n)
}

/// The native module.
#[pymodule]
fn _strider(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("StriderError", m.py().get_type::<StriderError>())?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(merge_json, m)?)?;
    m.add_function(wrap_pyfunction!(episode_count, m)?)?;
    m.add_class::<simulation::Simulation>()?;
    m.add_class::<fuzzy::Engine>()?;
    m.add_class::<anim::AnimationMdp>()?;
    Ok(())
}
