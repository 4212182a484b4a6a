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


class CtrlCWhen:
    """Delivers Ctrl-C to the main thread once a report of the run satisfies `happened`: an
    event of the run, not a time, so a busy machine cannot make it come early. Pass it as the
    run's `callback`."""

    def __init__(self, happened):
        self.happened = happened
        self.seen = threading.Event()
        self.thread = threading.Thread(target=self._interrupt, daemon=True)
        self.thread.start()

    def __call__(self, *report):
        if self.happened(*report):
            self.seen.set()
        return False

    def _interrupt(self):
        self.seen.wait()
        _thread.interrupt_main()

    def join(self):
        self.thread.join()


def when_compressed(start):
    """Ctrl-C once a `pack` run reports a φ above its start's."""
    return CtrlCWhen(lambda step, phi, values: phi > start.phi)


def test_interrupt_returns_the_best_packing(start):
    ctrl_c = when_compressed(start)
    r = packbench.pack("mls", start, seed=11, on_interrupt="return", callback=ctrl_c, **LONG)
    ctrl_c.join()
    assert r.termination == "interrupted"
    assert r.packing.n == start.n
    assert r.packing.phi > start.phi  # it compressed before it stopped
    assert r.metrics["phi"] == pytest.approx(r.packing.phi)


def test_interrupt_raises_keyboard_interrupt_carrying_the_result(start):
    ctrl_c = when_compressed(start)
    with pytest.raises(KeyboardInterrupt) as e:
        packbench.pack("mls", start, seed=11, callback=ctrl_c, **LONG)
    ctrl_c.join()
    r = e.value.result
    assert isinstance(r, packbench.Result)
    assert r.termination == "interrupted" and r.packing.phi > start.phi


def test_a_second_run_after_an_interrupt_is_not_stopped(start):
    # Each run has its own stop flag: an interrupted run does not stop the next one.
    ctrl_c = when_compressed(start)
    first = packbench.pack("mls", start, seed=11, on_interrupt="return", callback=ctrl_c, **LONG)
    ctrl_c.join()
    assert first.termination == "interrupted"
    p = packbench.initial_packing(40, 2, seed=12)
    r = packbench.pack("adam", p, seed=12)
    assert r.termination == "converged"


def test_compare_interrupted_keeps_finished_rows():
    # Ctrl-C when the first run (ls, seed 1) has finished: the second (mls down to 1e-9, minutes)
    # is stopped and the third and fourth are never started.
    ctrl_c = CtrlCWhen(lambda row: row["method"] == "ls")
    rows = packbench.compare(["ls", "mls"], n=300, dim=3, seeds=2, jobs=1,
                             params={"mls": LONG}, on_interrupt="return", callback=ctrl_c)
    ctrl_c.join()
    assert [(r["method"], r["seed"]) for r in rows] == [("ls", 1), ("mls", 1), ("ls", 2), ("mls", 2)]
    assert rows[0]["termination"] == "pressure_cap" and rows[0]["phi"] > 0.55
    # Stopped under way with its packing, or (if Ctrl-C lands before it starts) never started.
    assert (rows[1]["termination"], rows[1]["phi"] is None) in (("interrupted", False), ("not_run", True))
    assert [r["termination"] for r in rows[2:]] == ["not_run", "not_run"]


def test_a_compare_callback_sees_each_row_and_can_stop_it():
    seen = []

    def stop_after_the_first(row):
        seen.append((row["method"], row["seed"], row["phi"]))
        return True

    rows = packbench.compare(["ls", "mls"], n=300, dim=3, seeds=2, jobs=1,
                             params={"mls": LONG}, callback=stop_after_the_first)
    # The callback sees every row, the stopped ones too; the stop comes as the second run
    # starts or just before, so that run is stopped under way or never started.
    assert seen[0] == ("ls", 1, rows[0]["phi"]) and rows[0]["phi"] > 0.55
    assert sorted(seen[1:]) == sorted((r["method"], r["seed"], r["phi"]) for r in rows[1:])
    assert rows[1]["termination"] in ("interrupted", "not_run")
    assert [r["termination"] for r in rows[2:]] == ["not_run", "not_run"]
