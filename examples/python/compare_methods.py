"""Two methods from the same start: ADAM (soft spheres, Desmond & Weeks) and MLS
(Lubachevsky–Stillinger with a falling compression rate), their jamming densities φ_J side
by side, and — when matplotlib is installed — φ over each run and the two packings.

    pip install ./crates/python matplotlib   # from the repository root
    python examples/python/compare_methods.py
"""

import packbench

N, DIM, SEED = 200, 2, 1

# 2D bidisperse disks 1 : 1.4 in equal numbers (the classic glass former), φ = 0.05.
start = packbench.initial_packing(N, DIM, dist="bidisperse", d1=1.0, d2=1.4, p=0.5, seed=SEED)
results = {
    name: packbench.pack(name, start, seed=SEED, progress=True)
    for name in ("adam", "mls")
}

print(f"{'method':8} {'phi_J':>10} {'z_nonrattler':>13} {'rattlers':>9} {'runtime_s':>10}")
for name, r in results.items():
    m = r.metrics
    print(f"{name:8} {m['phi']:10.6f} {m['z_nonrattler']:13.3f} {m['rattlers']:9d} {r.runtime_s:10.2f}")
gap = results["mls"].metrics["phi"] - results["adam"].metrics["phi"]
print(f"phi_J(mls) - phi_J(adam) = {gap:+.2e}")

try:
    import matplotlib.pyplot as plt
    from matplotlib.collections import EllipseCollection
except ImportError:
    print("matplotlib is not installed: no figure")
else:
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2))
    for name, r in results.items():
        axes[0].plot(r.trace["time_s"], r.trace["phi"], label=name)
    axes[0].set(xlabel="time (s)", ylabel="φ", title="φ over the run")
    axes[0].legend()
    for ax, (name, r) in zip(axes[1:], results.items()):
        p = r.packing
        ax.add_collection(EllipseCollection(p.diameters, p.diameters, 0, units="xy",
                                            offsets=p.positions, offset_transform=ax.transData,
                                            facecolors="tab:blue", edgecolors="k", linewidths=0.3))
        ax.set(xlim=(0, p.box[0]), ylim=(0, p.box[1]), aspect="equal",
               title=f"{name}: φ_J = {r.metrics['phi']:.4f}")
    fig.tight_layout()
    fig.savefig("compare_methods.png", dpi=120)
    print("wrote compare_methods.png")
