# rcptools' answer to a "which parameter reaches this φ_J" question, which its CMA-ES search
# (it only maximises φ_J) cannot ask: a bracketing search over one parameter with rcptools' own
# distribution model and packer, as a user of rcptools would run it by hand.
#
#   python rcptools_target.py QUESTION SEED [N]
#
# QUESTION is one of
#   lognormal   the log-normal σ (std of ln D) whose packings jam at φ_J = 0.66: rcptools'
#               sweep model (sweep.build_sweep_model('lognormal', alpha = σ, a = 4), a log-normal
#               truncated at ±4σ in ln D), σ in [0.01, 0.4] (0.01 is the lowest alpha its model
#               accepts);
#   bidisperse  the smallest size ratio of a bidisperse mixture with equal numbers that reaches
#               φ_J = 0.65: make_universal_model with two `delta` components of equal weight
#               (equal number fractions) whose centres are the ratio apart, ratio in [1, 2].
# N = 1000 unless given, 3D, rcptools' search protocol (create_packing with phi_init 0.60,
# initializer_phi 0.11, speed "quick"; φ is create_packing's recomputed `phi`, what its search
# scores).
#
# The search, 2 seeds per point (the same 2 for every point), 16 points = 32 packings:
#   1. the two ends of the range;
#   2. 4 bisection steps on the mean φ_J of the midpoint (the bracket shrinks to 1/16);
#   3. 10 points evenly spaced inside the final bracket's centre ± 1/8 of the range (clipped to
#      the range; the window's own ends are not packed again);
#   4. a least-squares line of φ_J against the parameter through every point inside that window,
#      solved for the target (the bracket's linear interpolation if the slope is not positive),
#      clipped to the window.
# Then the answer is packed on 3 fresh seeds: 35 packings, as many as
# `packbench design ... --seeds-per-candidate 2 --budget 32 --confirm 3`. SEED picks the search
# seeds (1000 SEED, 1000 SEED + 1) and the confirmation seeds (10000 + 100 SEED + k, as in
# rcptools_mixture.py). Prints one line `RESULT {json}`. Runs in the virtual environment
# scripts/anchors/build.sh makes ($PACKBENCH_ANCHORS/venv-rcpg); rcptools is not a packbench
# dependency.
import json
import math
import multiprocessing as mp
import sys
from concurrent.futures import ProcessPoolExecutor

import numpy as np

NDIM = 3
PHI_INIT, INITIALIZER_PHI, SPEED = 0.60, 0.11, "quick"
SEEDS_PER_POINT, BISECTIONS, GRID, CONFIRM = 2, 4, 10, 3
A_TRUNC = 4.0  # the lognormal's truncation in units of σ (rcptools' `a`)
QUESTIONS = {
    # name: (parameter, lower, upper, target φ_J)
    "lognormal": ("sigma", 0.01, 0.4, 0.66),
    "bidisperse": ("ratio", 1.0, 2.0, 0.65),
}
# Centres of the two delta components in the span's linear R coordinate: inside the span so
# that neither is cut by its edge or by the Tukey window.
U1, U2 = 0.1, 0.9


def model(question, x):
    """rcptools' (MODEL, theta) for parameter value x."""
    from rcptools.model import initialize_theta, make_universal_model
    from rcptools.sweep import build_sweep_model

    if question == "lognormal":
        m, theta, _ = build_sweep_model("lognormal", x, A_TRUNC, NDIM)
        return m, theta
    if x <= 1.0 + 1e-9:
        comps = [{"type": "delta", "init": {"amp": 0.0, "R_center_u": 0.5}}]
        s = 1.01
    else:
        # R(u) = (1/t + u (t − 1/t)) / 2 with t² = S: R(U2) / R(U1) = x gives t² − 1 below.
        s = 1.0 + (x - 1.0) / (U2 - U1 * x)
        comps = [{"type": "delta", "init": {"amp": 0.0, "R_center_u": U1}},
                 {"type": "delta", "init": {"amp": 0.0, "R_center_u": U2}}]
    m = make_universal_model(comps, size_ratio=s, Ndim=NDIM, alpha_tukey=0.0025,
                             balance_rule="equal_count", name=f"bidisperse_r{x:.5g}")
    return m, initialize_theta(m, rule="from_spec")


def realized(question, x, n):
    """What rcptools' n sampled diameters (deterministic quantiles) really are."""
    from rcptools.model import sample_diameters

    m, theta = model(question, x)
    d = sample_diameters(theta, m, N=n)
    out = {"dmax_dmin": float(d.max() / d.min()), "cv": float(d.std() / d.mean())}
    if question == "lognormal":
        out["std_lnD"] = float(np.log(d).std())
    elif x > 1.0 + 1e-9:
        cut = 0.5 * (d.min() + d.max())
        small, large = d[d < cut], d[d >= cut]
        out.update(n_small=int(small.size), n_large=int(large.size),
                   ratio_of_means=float(large.mean() / small.mean()),
                   cv_within=float(max(small.std() / small.mean(),
                                       large.std() / large.mean())))
    return out


def pack(args):
    """φ of one packing: rcptools' create_packing on its model (one engine thread)."""
    question, x, seed, n = args
    from rcptools.jobs import _pin_worker_threads, create_packing

    _pin_worker_threads()
    m, theta = model(question, x)
    _, stats = create_packing(theta, m, N=n, Ndim=NDIM, seed=seed, phi_init=PHI_INIT,
                              initializer_phi=INITIALIZER_PHI, speed=SPEED)
    return float(stats["phi"])


def main():
    question, seed = sys.argv[1], int(sys.argv[2])
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 1000
    name, lo, hi, target = QUESTIONS[question]
    seeds = [1000 * seed + k for k in range(SEEDS_PER_POINT)]
    points = []  # (x, mean φ, [φ per seed])
    # Spawned workers are this process's children, so GNU time counts their CPU.
    with ProcessPoolExecutor(2, mp_context=mp.get_context("spawn")) as pool:

        def evaluate(xs):
            phis = list(pool.map(pack, [(question, x, s, n) for x in xs for s in seeds]))
            for i, x in enumerate(xs):
                p = phis[i * len(seeds):(i + 1) * len(seeds)]
                points.append((x, float(np.mean(p)), p))
                each = ", ".join(f"{v:.5f}" for v in p)
                print(f"{name} = {x:.5f}: φ_J {np.mean(p):.5f} ({each})", flush=True)
            return [points[-len(xs) + i][1] for i in range(len(xs))]

        phi_lo, phi_hi = evaluate([lo, hi])
        bracketed = phi_lo < target <= phi_hi
        a, b, fa, fb = lo, hi, phi_lo, phi_hi
        for _ in range(BISECTIONS):
            mid = 0.5 * (a + b)
            (f,) = evaluate([mid])
            if f < target:
                a, fa = mid, f
            else:
                b, fb = mid, f
        centre, half = 0.5 * (a + b), (hi - lo) / 8
        w_lo, w_hi = max(lo, centre - half), min(hi, centre + half)
        evaluate(list(np.linspace(w_lo, w_hi, GRID + 2)[1:-1]))
        inside = [(x, f) for x, f, _ in points if w_lo - 1e-12 <= x <= w_hi + 1e-12]
        xs, fs = np.array([p[0] for p in inside]), np.array([p[1] for p in inside])
        slope, intercept = np.polyfit(xs, fs, 1)
        if slope > 0:
            answer, how = (target - intercept) / slope, "least-squares line"
        elif fb != fa:
            answer, how = a + (target - fa) * (b - a) / (fb - fa), "bracket interpolation"
        else:
            answer, how = centre, "bracket centre"
        answer = float(min(max(answer, w_lo), w_hi))
        print(f"window [{w_lo:.5f}, {w_hi:.5f}], {len(inside)} points, slope {slope:.4f}: "
              f"{name} = {answer:.5f} ({how})", flush=True)
        confirm_seeds = [10_000 + 100 * seed + k for k in range(CONFIRM)]
        confirm = list(pool.map(pack, [(question, answer, s, n) for s in confirm_seeds]))
    search_phi = float(intercept + slope * answer) if slope > 0 else float("nan")
    print("RESULT " + json.dumps({
        "tool": "rcptools",
        "question": question,
        "seed": seed,
        "param": name,
        "answer": answer,
        "how": how,
        "target": target,
        "bracketed": bracketed,
        "search_phi": search_phi if math.isfinite(search_phi) else None,
        "confirm_phi": confirm,
        "points": [[x, f, p] for x, f, p in points],
        "N": n,
        "realized": realized(question, answer, n),
        "packings": len(points) * SEEDS_PER_POINT + CONFIRM,
    }))


# The worker pool starts processes that import this file: the search runs only here.
if __name__ == "__main__":
    main()
