"""A run interrupted from another thread (Ctrl-C delivered to the main thread, as
`_thread.interrupt_main` simulates it) stops and gives its best packing."""

import _thread
import signal
import threading

import pytest

import packbench

# MLS down to a compression rate of 1e-9 runs for minutes at N = 1000: only a stop ends it
# (should the stop never come, the budget of 10⁸ collisions, about a minute, ends it and the
# test fails on its termination instead of holding the suite).
LONG = dict(rate_final=1e-9, max_collisions=100_000_000)


@pytest.fixture(autouse=True)
def python_handles_ctrl_c():
    """A process started in the background by a non-interactive shell (`cmd &`) inherits
    SIGINT ignored, Python then installs no handler for it, and `_thread.interrupt_main` does
    nothing: these tests install Python's own handler for their duration."""
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, before)


@pytest.fixture(scope="module")
def start():
    return packbench.initial_packing(1000, 3, seed=11)


class CtrlCWhenCompressed:
    """Delivers Ctrl-C to the main thread once the run reports a φ above `phi`: an event of
    the run, not a time, so a busy machine cannot make it come before the run compresses.
    Pass it as the run's `callback`."""

    def __init__(self, phi):
        self.phi = phi
        self.seen = threading.Event()
        self.thread = threading.Thread(target=self._interrupt, daemon=True)
        self.thread.start()

    def __call__(self, step, phi, values):
        if phi > self.phi:
            self.seen.set()
        return False

    def _interrupt(self):
        self.seen.wait()
        _thread.interrupt_main()

    def join(self):
        self.thread.join()


def test_interrupt_returns_the_best_packing(start):
    ctrl_c = CtrlCWhenCompressed(start.phi)
    r = packbench.pack("mls", start, seed=11, on_interrupt="return", callback=ctrl_c, **LONG)
    ctrl_c.join()
    assert r.termination == "interrupted"
    assert r.packing.n == start.n
    assert r.packing.phi > start.phi  # it compressed before it stopped
    assert r.metrics["phi"] == pytest.approx(r.packing.phi)


def test_interrupt_raises_keyboard_interrupt_carrying_the_result(start):
    ctrl_c = CtrlCWhenCompressed(start.phi)
    with pytest.raises(KeyboardInterrupt) as e:
        packbench.pack("mls", start, seed=11, callback=ctrl_c, **LONG)
    ctrl_c.join()
    r = e.value.result
    assert isinstance(r, packbench.Result)
    assert r.termination == "interrupted" and r.packing.phi > start.phi


def test_a_second_run_after_an_interrupt_is_not_stopped(start):
    # Each run has its own stop flag: an interrupted run does not stop the next one.
    ctrl_c = CtrlCWhenCompressed(start.phi)
    first = packbench.pack("mls", start, seed=11, on_interrupt="return", callback=ctrl_c, **LONG)
    ctrl_c.join()
    assert first.termination == "interrupted"
    p = packbench.initial_packing(40, 2, seed=12)
    r = packbench.pack("adam", p, seed=12)
    assert r.termination == "converged"


def interrupt_after(seconds):
    timer = threading.Timer(seconds, _thread.interrupt_main)
    timer.start()
    return timer


def test_compare_interrupted_keeps_finished_rows(start):
    timer = interrupt_after(1.5)
    rows = packbench.compare(["ls", "mls"], n=300, dim=3, seeds=2, jobs=1,
                             params={"mls": LONG}, on_interrupt="return")
    timer.join()
    assert len(rows) == 4
    assert rows[0]["method"] == "ls" and rows[0]["phi"] is not None
    assert any(r["termination"] in ("interrupted", "not_run") for r in rows)
