//! Long runs from Python: the work runs on its own thread with the GIL released, while the
//! calling Python thread relays the progress it reports and polls for signals. Ctrl-C
//! (`KeyboardInterrupt`), or a callback that asks for it, sets the run's stop flag — the flag
//! the methods poll through `Observer::stop_flag`, the one the binary's Ctrl-C handler sets —
//! so the method returns its best packing before the exception is raised.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, SyncSender, TrySendError, sync_channel};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use packbench::records::RunRecord;
use packbench_core::Packing;
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

/// Snapshots of a run kept as frames (`pack(..., frames=K)`): every snapshot the method
/// passes is kept until there are 2K, then every other one is dropped and only every other
/// later one is kept, so the frames stay evenly spread over a run of any length.
pub struct FrameBuffer {
    /// How many frames the user asked for.
    pub wanted: usize,
    /// Keep one snapshot in `stride`.
    stride: u64,
    seen: u64,
    /// (step, packing) of the kept snapshots, in step order.
    pub kept: Vec<(u64, Packing)>,
}

impl FrameBuffer {
    pub fn new(wanted: usize) -> Self {
        FrameBuffer {
            wanted,
            stride: 1,
            seen: 0,
            kept: Vec::new(),
        }
    }

    fn push(&mut self, step: u64, packing: &Packing) {
        self.seen += 1;
        if !(self.seen - 1).is_multiple_of(self.stride) {
            return;
        }
        self.kept.push((step, packing.clone()));
        if self.kept.len() >= 2 * self.wanted.max(1) {
            let mut k = 0;
            self.kept.retain(|_| {
                k += 1;
                (k - 1) % 2 == 0
            });
            self.stride *= 2;
        }
    }

    /// At most `wanted` frames evenly spread over the kept ones, the last replaced by `last`
    /// (the run's final packing) at `last_step`.
    pub fn finish(mut self, last_step: u64, last: &Packing) -> Vec<(u64, Packing)> {
        if self.kept.last().is_none_or(|(s, _)| *s != last_step) {
            self.kept.push((last_step, last.clone()));
        } else if let Some(f) = self.kept.last_mut() {
            f.1 = last.clone();
        }
        let n = self.kept.len();
        let k = self.wanted.min(n);
        if k <= 1 {
            return self.kept.split_off(n - k);
        }
        // Evenly spread, first and last kept.
        let picks: Vec<usize> = (0..k).map(|i| i * (n - 1) / (k - 1)).collect();
        let mut out = Vec::with_capacity(k);
        for (i, f) in self.kept.into_iter().enumerate() {
            if picks.contains(&i) {
                out.push(f);
            }
        }
        out
    }
}

/// The sending end a job reports through; sends never block the job.
#[derive(Clone)]
pub struct Reports {
    tx: SyncSender<Event>,
    stop: &'static AtomicBool,
    frames: Option<Arc<Mutex<FrameBuffer>>>,
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
    fn snapshot(&mut self, step: u64, packing: &Packing) {
        if let Some(f) = &self.reports.frames
            && let Ok(mut f) = f.lock()
        {
            f.push(step, packing);
        }
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
    frames: Option<Arc<Mutex<FrameBuffer>>>,
    job: impl FnOnce(Reports) -> T + Send,
    mut on_event: impl FnMut(Python<'_>, Event) -> PyResult<bool>,
) -> PyResult<Supervised<T>> {
    let slot = StopSlot::claim()?;
    let stop = slot.flag();
    let (tx, rx) = sync_channel(QUEUE);
    let reports = Reports { tx, stop, frames };
    std::thread::scope(|scope| {
        let worker = scope.spawn(move || crate::threads::install(|| job(reports)));
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
