"""The progress bar measures the method's own progress towards its stopping rule and ends full
when the method converges; without tqdm it draws tqdm's bar on stderr."""

import re

import pytest

import packbench
import packbench._progress as progress_module


@pytest.fixture
def no_tqdm(monkeypatch):
    monkeypatch.setattr(progress_module, "_tqdm", None)
    monkeypatch.setattr(progress_module, "_LINE_EVERY_S", 0.0)


def bar_lines(stderr, label):
    return [line for line in stderr.splitlines() if line.startswith(f"{label}: ")]


def test_a_converged_adam_run_ends_at_100_percent(no_tqdm, capsys):
    p = packbench.initial_packing(300, 3, seed=2)
    r = packbench.pack("adam", p, seed=2, progress=True)
    assert r.termination == "converged"
    lines = bar_lines(capsys.readouterr().err, "adam")
    assert lines, "no bar drawn"
    assert re.match(r"adam: 100%\|#{20}\| \d\d:\d\d", lines[-1]), lines[-1]
    assert not any(line.split(": ", 1)[1].startswith(",") for line in lines)


def test_progress_follows_the_stopping_rule_not_the_budget():
    seen = []
    # mls: γ falls from rate_initial to rate_final; its progress is that fall on a log scale
    # (a rate_final of 1e-2 keeps the run to a few seconds).
    r = packbench.pack("mls", packbench.initial_packing(300, 3, seed=3, placement="poisson"),
                       seed=3, rate_final=1e-2, callback=lambda step, phi, v: seen.append(dict(v)))
    assert r.termination in ("rate_final", "jammed", "converged"), r.termination
    fractions = [v["progress"] for v in seen if "progress" in v]
    assert fractions, seen[:3]
    assert all(b >= a for a, b in zip(fractions, fractions[1:]))  # never goes back
    assert all(0.0 <= f <= 1.0 for f in fractions) and fractions[-1] > 0.5
    # the budget is far from used, the stopping rule is what the bar shows
    assert all(v.get("fraction") is None for v in seen)


def test_the_interrupted_bar_is_not_filled(no_tqdm, capsys):
    p = packbench.initial_packing(300, 3, seed=4)
    r = packbench.pack("adam", p, seed=4, progress=True, max_steps=300)
    # Stopped by its budget; the bench names a budget run that still overlaps as such.
    assert r.termination in ("max_steps", "max_steps_with_overlaps"), r.termination
    last = bar_lines(capsys.readouterr().err, "adam")[-1]
    assert not last.startswith("adam: 100%"), last
