# Are rcptools' mixture answers sound packings when their largest spheres are wider than half the
# periodic box (which packbench's adam refused before it counted further images)? Repacks the first confirmation packing of the
# answer of each search seed given and reports D_max / L, the largest overlap rcptools reports
# (its minimum-image one), and the overlaps between spheres through any periodic image other
# than the nearest one (27 images per pair of spheres, for pairs with at least one large sphere).
#
#   python rcptools_images.py OUT/mixture SEED...
#
# OUT/mixture is the folder examples/design/against_rcptools.sh filled (rcptools-S.log); run it
# in $PACKBENCH_ANCHORS/venv-rcpg as rcptools_mixture.py.
import itertools
import json
import re
import sys
from pathlib import Path

import numpy as np
from rcptools.jobs import create_packing
from rcptools.studies import _gaussian_only_model


def main():
    folder, seeds = Path(sys.argv[1]), [int(s) for s in sys.argv[2:]]
    model, _ = _gaussian_only_model(2, 10.0, 3, name="cmp_mix2_sr10")
    for seed in seeds:
        log = (folder / f"rcptools-{seed}.log").read_text()
        r = json.loads(re.search(r"^RESULT (.*)$", log, re.M)[1])
        # rcptools_mixture.py's first confirmation seed and the search's packing protocol.
        packing, stats = create_packing(np.array(r["theta"]), model, N=1000, Ndim=3,
                                        seed=10_000 + 100 * seed, phi_init=0.60,
                                        initializer_phi=0.11, speed="quick")
        x = np.asarray(packing.positions, dtype=float)
        d = np.asarray(packing.diameters, dtype=float)
        box = np.asarray(packing.box, dtype=float)
        large = np.flatnonzero(d > 0.5 * (d.min() + d.max()))
        shifts = np.array([s for s in itertools.product((-1, 0, 1), repeat=3)], dtype=float)
        count, worst = 0, 0.0
        for i in large:
            sep = x - x[i]
            sep -= box * np.round(sep / box)  # the nearest image
            for shift in shifts:
                if not shift.any():
                    continue
                dist = np.linalg.norm(sep + shift * box, axis=1)
                contact = 0.5 * (d[i] + d)
                hit = dist < contact
                hit[i] = False
                hit[large[large < i]] = False  # each pair of large spheres once
                if hit.any():
                    count += int(hit.sum())
                    worst = max(worst, float((1 - dist[hit] / contact[hit]).max()))
        print(f"search {seed}: φ {stats['phi']:.4f}, {large.size} large spheres, "
              f"D_max/L {d.max() / box[0]:.3f}, largest overlap {stats['max_overlap']:.2e}; "
              f"{count} overlaps through another image, the largest {worst:.2e}")


if __name__ == "__main__":
    main()
