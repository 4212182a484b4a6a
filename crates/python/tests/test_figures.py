"""Figures from Python: `Packing.plot()` draws to scale with matplotlib, and packings and
results show inline in Jupyter as the `packbench view` page."""

import base64
import json
import math
import re

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402

import packbench  # noqa: E402


def test_plot_draws_every_disk_to_scale():
    p = packbench.initial_packing(30, 2, phi=0.3, seed=1, walls=[1, 1])
    ax = p.plot()
    (coll,) = ax.collections
    # walled on both axes: no periodic images, one disk per particle, each of its radius
    paths = coll.get_paths()
    assert len(paths) == 30
    widths = sorted(path.get_extents().width for path in paths)
    np.testing.assert_allclose(widths, sorted(p.diameters), rtol=1e-6)
    assert ax.get_xlim() == (0.0, 1.0) and ax.get_aspect() == 1.0


def test_plot_of_a_3d_packing_is_a_slice():
    p = packbench.initial_packing(400, 3, phi=0.3, seed=2)
    ax = p.plot(at=0.5)
    (coll,) = ax.collections
    z = p.positions[:, 2]
    r = p.diameters / 2
    cut = np.abs(z - 0.5) < r
    assert len(coll.get_paths()) >= cut.sum() > 0  # periodic images may add disks
    assert "slice x2 = 0.5" in ax.get_title()


def page_data(html):
    """The JSON data block of the viewer page inside the iframe's srcdoc."""
    assert html.startswith("<iframe") and "srcdoc=" in html
    doc = html.split('srcdoc="', 1)[1].split('" style=', 1)[0]
    doc = doc.replace("&quot;", '"').replace("&amp;", "&")
    m = re.search(r'<script type="application/json" id="[^"]+">(.*?)</script>', doc, re.S)
    assert m, doc[:300]
    return json.loads(m.group(1).replace("\\u003c", "<").replace("\\u003e", ">").replace("\\u0026", "&"))


def test_packing_and_result_show_as_the_viewer_page():
    start = packbench.initial_packing(40, 2, dist="bidisperse", d1=1, d2=1.4, p=0.5, seed=3)
    data = page_data(start._repr_html_())
    (panel,) = data["panels"]
    frame = panel["frames"][0]
    assert frame["n"] == 40 and math.isclose(frame["phi"], start.phi)
    xs = np.frombuffer(base64.b64decode(frame["positions"]), dtype="<f4").reshape(40, 2)
    np.testing.assert_allclose(xs, start.positions, rtol=1e-6)
    r = packbench.pack("adam", start, seed=3)
    data = page_data(r._repr_html_())
    (panel,) = data["panels"]
    assert panel["method"] == "adam" and panel["termination"] == r.termination
    assert len(panel["trace"]["phi"]) == len(r.trace["phi"])
    assert panel["frames"][0]["metrics"]["phi"] == r.metrics["phi"]
