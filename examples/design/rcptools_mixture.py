# rcptools' search on the question of packbench's mixture example: the densest 3D mixture of two
# Gaussian components with size ratio 10, N = 1000; 6 generations x 9 candidates x 1 cheap seed
# plus rcptools' own elite reruns (1 a generation), then the best candidate confirmed on 3 fresh
# seeds: 63 packings, as many as `packbench design ... --budget 60 --confirm 3`.
#
#   python rcptools_mixture.py OUT SEED
#
# SEED is rcptools' master seed. Prints one line `RESULT {json}`: the best theta, its search
# mean, the confirmation's φ_J, the packings made. Run it in the virtual environment
# scripts/anchors/build.sh makes ($PACKBENCH_ANCHORS/venv-rcpg): rcptools ships with
# RCPGenerator 1.0's Python package and is not a packbench dependency.
import json
import os
import sys

from rcptools import run_or_resume_search
from rcptools.search import run_validation
from rcptools.studies import _gaussian_only_model, default_config

NDIM, N, GENERATIONS, POPULATION, CONFIRM = 3, 1000, 6, 9, 3


def main():
    out, seed = sys.argv[1], int(sys.argv[2])
    # Workers started by spawn are this process's children, so GNU time counts their CPU
    # (rcptools' default forkserver hides it).
    os.environ["RCP_MP_CONTEXT"] = "spawn"
    model, theta = _gaussian_only_model(2, 10.0, NDIM, name="cmp_mix2_sr10")
    cfg = default_config(search_name="cmp_mix2_sr10", save_dir=out, Ndim=NDIM, N=N,
                         generations=GENERATIONS, population_size=POPULATION,
                         cheap_seeds_per_candidate=1, elite_count=1, elite_extra_seeds=1,
                         master_seed=seed)
    cfg["n_workers"] = 2
    cfg["reserve_cpus"] = 0
    cfg["progress_enabled"] = False
    best_theta, state = run_or_resume_search(theta, cfg, model)
    best = state["best_result"]
    # The confirmation packs the best distribution itself: rcptools' geometric pre-screen (a
    # bound on D_max for the search's candidates) would reject a fresh draw of it unpacked.
    cfg["prescreen_enabled"] = False
    confirm_seeds = [10_000 + 100 * seed + k for k in range(CONFIRM)]
    agg, _ = run_validation(best_theta, cfg, model, seeds=confirm_seeds, label="confirmation")
    print("RESULT " + json.dumps({
        "tool": "rcptools",
        "seed": seed,
        "theta": [float(x) for x in best_theta],
        "search_phi": float(best["mean_phi"]),
        "confirm_phi": [float(p) for p in agg["phis"]],
        "packings": GENERATIONS * POPULATION + GENERATIONS + CONFIRM,
    }))


# rcptools' worker pool starts processes that import this file: the search runs only here.
if __name__ == "__main__":
    main()
