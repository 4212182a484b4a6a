//! Long runs from Python: the work runs on its own thread with the GIL released, while the
//! calling Python thread relays the progress it reports and polls for signals. Ctrl-C
//! (`KeyboardInterrupt`), or a callback that asks for it, sets the run's stop flag — the flag
//! the methods poll through `Observer::stop_flag`, the one the binary's Ctrl-C handler sets —
//! so the method returns its best packing before the exception is raised.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, SyncSender, TrySendError, sync_channel};
use std::time::Duration;

use packbench::records::RunRecord;
use packbench_core::run::{Observer, Progress};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// How often the Python thread looks for signals while it waits.
const POLL: Duration = Duration::from_millis(50);

/// Progress events not yet relayed before newer ones are dropped (a method reports a few times
/// per second; only a stalled callback lets them pile up).
const QUEUE: usize = 64;

/// Runs that can be stopped at once, each with its own flag (`Observer::stop_flag` hands out
/// `&'static` flags, so they live in a fixed table and are reused).
const SLOTS: usize = 64;
static STOP: [AtomicBool; SLOTS] = [const { AtomicBool::new(false) }; SLOTS];
static TAKEN: [AtomicBool; SLOTS] = [const { AtomicBool::new(false) }; SLOTS];

/// One entry of the stop-flag table, cleared and given back when dropped.
struct StopSlot(usize);

impl StopSlot {
    fn claim() -> PyResult<Self> {
        (0..SLOTS)
            .find(|&k| {
                TAKEN[k]
                    .compare_exchange(false, true, Ordering::SeqCst, Ordering::SeqCst)
                    .is_ok()
            })
            .map(|k| {
                STOP[k].store(false, Ordering::SeqCst);
                StopSlot(k)
            })
            .ok_or_else(|| {
                PyRuntimeError::new_err(format!(
                    "more than {SLOTS} packbench runs at once in one process; wait for one to finish"
                ))
            })
    }

    fn flag(&self) -> &'static AtomicBool {
        &STOP[self.0]
    }
}

impl Drop for StopSlot {
    fn drop(&mut self) {
        STOP[self.0].store(false, Ordering::SeqCst);
        TAKEN[self.0].store(false, Ordering::SeqCst);
    }
}

/// What a running job reports to the Python thread.
pub enum Event {
    /// A method's progress report.
    Progress(Progress),
    /// A finished run of a comparison.
    RunDone(Box<RunRecord>),
}

/// The sending end a job reports through; sends never block the job.
#[derive(Clone)]
pub struct Reports {
    tx: SyncSender<Event>,
    stop: &'static AtomicBool,
}

impl Reports {
    /// Reports `event`; dropped when the queue is full.
    pub fn send(&self, event: Event) {
        if let Err(TrySendError::Full(_)) = self.tx.try_send(event) {
            // The Python side is behind; a later report supersedes this one.
        }
    }

    /// An observer that relays progress and carries the run's stop flag.
    pub fn observer(&self) -> RelayObserver {
        RelayObserver {
            reports: self.clone(),
        }
    }
}

/// The observer of a run started from Python.
pub struct RelayObserver {
    reports: Reports,
}

impl Observer for RelayObserver {
    fn progress(&mut self, p: &Progress) {
        self.reports.send(Event::Progress(p.clone()));
    }
    fn stop_flag(&self) -> Option<&'static AtomicBool> {
        Some(self.reports.stop)
    }
}

/// How a supervised job ended from Python's side: its value, and the exception that stopped
/// it early (a `KeyboardInterrupt`, or one raised by the event handler), if any.
pub struct Supervised<T> {
    pub value: T,
    pub stopped_by: Option<PyErr>,
}

/// Runs `job` on a new thread with the GIL released. The calling thread hands each reported
/// event to `on_event` (with the GIL; returning `Ok(true)` asks the job to stop) and polls
/// for signals; a signal's exception or an error of `on_event` sets the stop flag and is
/// returned once the job has finished. A panic of the job is a `RuntimeError`.
pub fn supervise<T: Send>(
    py: Python<'_>,
    job: impl FnOnce(Reports) -> T + Send,
    mut on_event: impl FnMut(Python<'_>, Event) -> PyResult<bool>,
) -> PyResult<Supervised<T>> {
    let slot = StopSlot::claim()?;
    let stop = slot.flag();
    let (tx, rx) = sync_channel(QUEUE);
    let reports = Reports { tx, stop };
    std::thread::scope(|scope| {
        let worker = scope.spawn(move || job(reports));
        let mut rx: Receiver<Event> = rx;
        let mut stopped_by: Option<PyErr> = None;
        loop {
            let (back, next) = py.detach(move || {
                let next = rx.recv_timeout(POLL);
                (rx, next)
            });
            rx = back;
            match next {
                Ok(event) if stopped_by.is_none() => match on_event(py, event) {
                    Ok(false) => {}
                    Ok(true) => stop.store(true, Ordering::SeqCst),
                    Err(e) => {
                        stopped_by = Some(e);
                        stop.store(true, Ordering::SeqCst);
                    }
                },
                Ok(_) | Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => break,
            }
            if stopped_by.is_none()
                && let Err(e) = py.check_signals()
            {
                stopped_by = Some(e);
                stop.store(true, Ordering::SeqCst);
            }
        }
        let value = py
            .detach(move || worker.join())
            .map_err(|panic| PyRuntimeError::new_err(panic_message(&panic)))?;
        Ok(Supervised { value, stopped_by })
    })
}

/// The message of a panic payload.
fn panic_message(panic: &Box<dyn std::any::Any + Send>) -> String {
    let what = panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into());
    format!("packbench failed unexpectedly (a panic, which is a bug): {what}")
}
