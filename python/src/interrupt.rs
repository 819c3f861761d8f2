//! Running glint work with the GIL released while Ctrl-C still works.
//!
//! Python handles SIGINT by setting a flag that only its main thread acts on, and only while it
//! runs Python code or calls `PyErr_CheckSignals`. A render on the calling thread would block
//! that for its whole length, so the work runs on a scoped thread while the calling thread,
//! without the GIL, waits for it in short slices and checks for signals between them (taking
//! the GIL for the check alone). On a signal it sets the render's cancellation flag, which the
//! tile scheduler polls before each tile, waits for the render to stop, and raises what the
//! signal handler raised (`KeyboardInterrupt` for Ctrl-C).

use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

/// How often the waiting thread checks for signals: short enough that Ctrl-C feels immediate,
/// long enough to cost nothing (the result itself wakes the thread at once).
const SIGNAL_CHECK: Duration = Duration::from_millis(50);

/// Runs `work` with the GIL released; `work` receives the cancellation flag to hand to the
/// renderer; `doing` names the work for a panic's report ("rendering scene.gltf"). Returns
/// its result, or the signal handler's exception if a signal arrived (the work's own result is
/// then dropped), or a `GlintError` if the work panicked (one line: the panic's message, see
/// [`glint::panics`]; never pyo3's `PanicException`).
pub fn run_detached<T, F>(py: Python<'_>, doing: &str, work: F) -> PyResult<T>
where
    T: Send,
    F: FnOnce(&AtomicBool) -> T + Send,
{
    let cancel = AtomicBool::new(false);
    py.detach(|| {
        std::thread::scope(|scope| {
            let (done, finished) = mpsc::channel();
            let cancel = &cancel;
            scope.spawn(move || {
                // Caught here: a panicking scoped thread would re-panic in `scope` itself.
                let result = glint::panics::catch(|| work(cancel));
                // The receiver only goes away once this thread is done.
                let _ = done.send(result);
            });
            let mut interrupted: Option<PyErr> = None;
            loop {
                match finished.recv_timeout(SIGNAL_CHECK) {
                    Ok(result) => {
                        return match (interrupted, result) {
                            (Some(err), _) => Err(err),
                            (None, Ok(result)) => Ok(result),
                            (None, Err(panic)) => Err(crate::glint_error(panic.report(doing))),
                        };
                    }
                    Err(mpsc::RecvTimeoutError::Timeout) => {
                        if interrupted.is_none()
                            && let Err(err) = Python::attach(|py| py.check_signals())
                        {
                            cancel.store(true, Ordering::Relaxed);
                            interrupted = Some(err);
                        }
                    }
                    // Cannot happen (the sender always sends); treated as a failed render.
                    Err(mpsc::RecvTimeoutError::Disconnected) => {
                        return Err(interrupted.unwrap_or_else(|| {
                            crate::glint_error("the render thread stopped without a result")
                        }));
                    }
                }
            }
        })
    })
}
