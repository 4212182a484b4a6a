# rcptools' search on the question of packbench's mixture example: densest 3D mixture of two
# Gaussian components, size ratio 10, N = 1000, 6 generations x 9 candidates x 1 cheap seed.
# (The reference run behind docs/BENCHMARKS.md, Design: python rcptools_mixture.py OUT in the
# virtual environment scripts/anchors/build.sh makes (anchors/venv-rcpg); rcptools ships with
# RCPGenerator's Python package and is not a packbench dependency.)
import sys, time, json
import numpy as np
from rcptools.studies import _gaussian_only_model, default_config
from rcptools import run_or_resume_search
Ndim, N = 3, 1000
model, theta = _gaussian_only_model(2, 10.0, Ndim, name="cmp_mix2_sr10")
cfg = default_config(search_name="cmp_mix2_sr10", save_dir=sys.argv[1], Ndim=Ndim, N=N,
                     generations=6, population_size=9, cheap_seeds_per_candidate=1,
                     elite_count=1, elite_extra_seeds=1)
cfg["n_workers"] = 2
cfg["reserve_cpus"] = 0
t0 = time.time()
res = run_or_resume_search(theta, cfg, model)
print("wall", time.time() - t0)
try:
    print(json.dumps(res, default=str)[:3000])
except Exception as e:
    print("result", type(res), e)
