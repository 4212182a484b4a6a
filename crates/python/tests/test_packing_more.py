"""Periodic positions outside the box, rescaling a packing (with_phi, with_box), relaxing it
to a target φ, contact_tol reaching closest-jammed, the trace of every step, frames of a run,
thread counts, and compare's refine and knob_value."""

import numpy as np
import pytest

import packbench


def test_periodic_positions_outside_the_box_are_a_value_error():
    x = np.array([[0.2, 0.3], [2.497, 0.5]])
    with pytest.raises(ValueError, match=r"positions\[1, 0\] = 2.497 lies outside the periodic box"):
        packbench.Packing(x, [0.1, 0.1])
    with pytest.raises(ValueError, match="outside the periodic box"):
        packbench.pack("adam", (x, [0.1, 0.1]))
    # wrapped, as the message says, it is accepted where it belongs
    p = packbench.Packing(x % 1.0, [0.1, 0.1])
    assert p.positions[1, 0] == pytest.approx(0.497)
    # a walled axis refuses a centre outside too
    with pytest.raises(ValueError, match="outside the container"):
        packbench.Packing(np.array([[0.5, 0.5], [1.2, 0.5]]), [0.1, 0.1], walls=[1, 0])


def test_with_phi_and_with_box_rescale():
    p = packbench.initial_packing(100, 3, seed=1)
    q = p.with_phi(0.2)
    assert q.phi == pytest.approx(0.2, rel=1e-12)
    assert q.positions.tobytes() == p.positions.tobytes()
    b = p.with_box([2.0, 1.0, 1.0])
    assert b.box == [2.0, 1.0, 1.0] and b.phi == pytest.approx(p.phi / 2)
    np.testing.assert_allclose(b.positions[:, 0], 2 * p.positions[:, 0])
    with pytest.raises(ValueError, match="phi=1.5"):
        p.with_phi(1.5)
    with pytest.raises(ValueError, match="box= has 2 lengths"):
        p.with_box([1.0, 1.0])


def test_relax_grows_to_a_target_phi_overlap_free():
    p = packbench.initial_packing(200, 3, seed=2)
    r = p.relax("fire", target_phi=0.55, seed=2)
    assert r.method == "fire" and r.termination == "target_reached", r.termination
    assert r.packing.phi == pytest.approx(0.55, abs=1e-9)
    assert r.metrics["max_overlap"] < 1e-3


def test_contact_tol_reaches_closest_jammeds_parameter():
    p = packbench.initial_packing(20, 2, dist="bidisperse", d1=1, d2=1.4, p=0.5, seed=1)
    r = packbench.pack("closest-jammed", p, seed=1, contact_tol=1e-8)
    assert r.params["contact_tol"] == 1e-8
    # the default leaves closest-jammed's own default (1e-9) and analyses at 1e-6
    assert packbench.pack("closest-jammed", p, seed=1).params["contact_tol"] == 1e-9
    with pytest.raises(ValueError, match="contact_tol=-1"):
        packbench.pack("adam", p, contact_tol=-1.0)


def test_trace_every_step():
    p = packbench.initial_packing(50, 2, dist="bidisperse", d1=1, d2=1.4, p=0.5, seed=3)
    r = packbench.pack("adam", p, seed=3, trace_every=1)
    steps = r.trace["step"].astype(np.int64)
    # every step is a row but the few where the protocol changes phase (evaluated without
    # a minimiser step), and the final state is the last row
    missing = set(range(1, r.steps + 1)) - set(steps.tolist())
    assert len(missing) <= 3, sorted(missing)[:10]
    assert steps[-1] == r.steps and np.all(np.diff(steps) >= 0)
    default = packbench.pack("adam", p, seed=3)
    assert len(default.trace["step"]) < len(steps)
    assert default.packing.positions.tobytes() == r.packing.positions.tobytes()
    with pytest.raises(ValueError, match="trace_every applies to adam and fire"):
        packbench.pack("ls", p, trace_every=1)


def test_frames_are_snapshots_of_the_run():
    p = packbench.initial_packing(80, 2, dist="bidisperse", d1=1, d2=1.4, p=0.5, seed=5)
    r = packbench.pack("adam", p, seed=5, frames=6)
    f = r.frames
    assert f["positions"].shape == (6, 80, 2) and f["diameters"].shape == (6, 80)
    assert f["phi"].shape == (6,) and f["box"].shape == (6, 2)
    assert np.all(np.diff(f["step"].astype(np.int64)) > 0)
    assert f["phi"][-1] == pytest.approx(r.packing.phi)
    assert f["positions"][-1].tobytes() == r.packing.positions.tobytes()
    assert f["phi"][0] < f["phi"][-1]  # the run compresses
    # frames do not change the run
    assert packbench.pack("adam", p, seed=5).packing == r.packing
    # seq-fill adds particles as it goes: its frames are lists, one array per frame
    s = packbench.pack("seq-fill", p, seed=5, frames=3).frames
    assert isinstance(s["positions"], list) and len(s["positions"]) == len(s["phi"]) <= 3
    assert [x.shape[0] for x in s["positions"]] == [len(dia) for dia in s["diameters"]]


def test_thread_count_does_not_change_the_bits():
    p = packbench.initial_packing(5000, 2, seed=6, phi=0.3)
    try:
        packbench.set_num_threads(1)
        assert packbench.get_num_threads() == 1
        one = packbench.pack("adam", p, seed=6, max_steps=200, force_balance=False)
        packbench.set_num_threads(2)
        two = packbench.pack("adam", p, seed=6, max_steps=200, force_balance=False)
    finally:
        packbench.set_num_threads(None)
    assert one.packing.positions.tobytes() == two.packing.positions.tobytes()
    with pytest.raises(ValueError, match="n=0"):
        packbench.set_num_threads(0)


def test_compare_refuses_a_refinement_that_does_not_jam_exactly():
    with pytest.raises(ValueError, match="refine=\"adam\": a refinement must jam exactly"):
        packbench.compare("ls", n=10, dim=2, seeds=1, refine="adam")


def test_compare_rows_carry_the_accuracy_knob():
    rows = packbench.compare(["adam", "ls"], n=20, dim=2, seeds=1, params={"ls": {"rate": 0.5}})
    knobs = {m["name"]: m["accuracy_knob"] for m in packbench.methods()}
    defaults = {m["name"]: m["params"] for m in packbench.methods()}
    by = {r["method"]: r for r in rows}
    assert by["ls"]["knob_value"] == 0.5
    assert by["adam"]["knob_value"] == defaults["adam"][knobs["adam"]]


def test_the_module_docstring_counts_the_methods():
    n = len(packbench.methods())
    words = {7: "seven", 8: "eight", 9: "nine"}
    assert words[n] in packbench.__doc__ and words[n] in packbench._packbench.__doc__


def test_fixed_diameters_stay_while_the_others_jam_around_them():
    # RCPGenerator's mask of fixed diameters: large spheres held, the small ones grow and jam.
    p = packbench.initial_packing(240, 3, phi=0.3, dist="bidisperse", d1=1.0, d2=3.0, p=0.9,
                                  seed=8, placement="random")
    d0 = p.diameters
    held = d0 > 2.0 * d0.min()
    assert 5 < held.sum() < 60
    for method in ["adam", "fire"]:
        r = packbench.pack(method, p, fixed=held)
        assert r.termination == "converged", (method, r.termination)
        d = r.packing.diameters
        assert np.array_equal(d[held], d0[held])
        scale = d[~held] / d0[~held]
        assert np.ptp(scale) < 1e-12 * scale.mean() and scale.mean() > 1.1
        assert r.metrics["max_overlap"] < 1e-3
        assert abs(r.metrics["iso_gap"]) <= 0.03 * r.metrics["n_dof"]
        # the same list of indices as a parameter gives the same bits
        same = packbench.pack(method, p, fixed_diameters=np.flatnonzero(held).tolist())
        assert same.packing.positions.tobytes() == r.packing.positions.tobytes()


def test_fixed_is_refused_where_it_cannot_apply():
    p = packbench.initial_packing(50, 3, seed=1)
    with pytest.raises(ValueError, match="fixed: mls holds no diameters fixed"):
        packbench.pack("mls", p, fixed=[0])
    with pytest.raises(ValueError, match="fixed: index 50 names no particle"):
        packbench.pack("adam", p, fixed=[1, 50])
    with pytest.raises(ValueError, match="one boolean per particle, N = 50; got 3"):
        packbench.pack("adam", p, fixed=[True, False, True])
    with pytest.raises(ValueError, match="holds every diameter"):
        packbench.pack("adam", p, fixed=np.ones(50, dtype=bool))
