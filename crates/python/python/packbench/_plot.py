"""``Packing.plot()``: a packing drawn to scale with matplotlib (2D disks, or the disks a
plane cuts out of a 3D or higher-dimensional packing)."""

import numpy as np


def plot_packing(packing, ax=None, *, axis=None, at=None, color="tab:blue", edgecolor="k",
                 linewidth=0.3, box=True):
    """Draws ``packing`` on matplotlib axes ``ax`` (new ones when None) and returns them.

    2D: every disk to scale. d ≥ 3: the slice through the plane ``x[axis] = at`` (default:
    the last axis, at half its length), each sphere it cuts drawn as the disk of the cut,
    radius √(r² − Δ²) with Δ its centre's distance to the plane (minimum image on a periodic
    axis); the in-plane axes are the first two others. ``box`` outlines the container's box.
    """
    import matplotlib.pyplot as plt
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle, Rectangle

    x = packing.positions
    r = packing.diameters / 2
    lengths = np.asarray(packing.box, dtype=float)
    periodic = [w == 0 for w in (packing.walls or [1] * packing.dim)]
    d = packing.dim
    if ax is None:
        _, ax = plt.subplots(figsize=(5, 5))
    if d == 2:
        plane = [0, 1]
        centres, radii = x, r
        title = f"N = {packing.n}, φ = {packing.phi:.4f}"
    else:
        axis = d - 1 if axis is None else int(axis)
        if not 0 <= axis < d:
            raise ValueError(f"axis={axis}: the packing has axes 0 … {d - 1}")
        at = lengths[axis] / 2 if at is None else float(at)
        delta = x[:, axis] - at
        if periodic[axis]:
            delta -= lengths[axis] * np.round(delta / lengths[axis])
        cut = np.abs(delta) < r
        plane = [k for k in range(d) if k != axis][:2]
        centres = x[cut][:, plane]
        radii = np.sqrt(r[cut] ** 2 - delta[cut] ** 2)
        title = f"slice x{axis} = {at:.4g}: {int(cut.sum())} of N = {packing.n}, φ = {packing.phi:.4f}"
    patches = [Circle((cx, cy), rad) for (cx, cy), rad in zip(centres, radii)]
    # Periodic images of disks that cross an in-plane periodic boundary.
    for k, (c_axis) in enumerate(plane):
        if not periodic[c_axis]:
            continue
        length = lengths[c_axis]
        for (cx, cy), rad in zip(centres, radii):
            c = (cx, cy)[k]
            for shift in (-length, length):
                if (c + shift - rad < length) and (c + shift + rad > 0):
                    moved = [cx, cy]
                    moved[k] += shift
                    patches.append(Circle(tuple(moved), rad))
    ax.add_collection(PatchCollection(patches, facecolor=color, edgecolor=edgecolor,
                                      linewidth=linewidth))
    if box:
        ax.add_patch(Rectangle((0, 0), lengths[plane[0]], lengths[plane[1]], fill=False,
                               edgecolor="0.3", linewidth=0.8))
    ax.set_xlim(0, lengths[plane[0]])
    ax.set_ylim(0, lengths[plane[1]])
    ax.set_aspect("equal")
    ax.set_xlabel(f"x{plane[0]}")
    ax.set_ylabel(f"x{plane[1]}")
    ax.set_title(title)
    return ax
