"""The example notebook runs headless (nbclient) and its outputs hold the inline viewer and a
figure."""

import pathlib

import nbformat
from nbclient import NotebookClient

NOTEBOOK = pathlib.Path(__file__).resolve().parents[1] / "examples" / "quickstart.ipynb"


def test_quickstart_notebook_shows_the_viewer_and_a_figure(tmp_path):
    nb = nbformat.read(NOTEBOOK, as_version=4)
    NotebookClient(nb, timeout=300, kernel_name="python3",
                   resources={"metadata": {"path": str(tmp_path)}}).execute()
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    metrics = outputs[0]["data"]["text/plain"]
    assert "'isostatic': True" in metrics, metrics
    html = [o["data"]["text/html"] for o in outputs if "text/html" in o.get("data", {})]
    assert any(h.startswith("<iframe") and "packbench-data" in h for h in html)
    assert any("image/png" in o.get("data", {}) for o in outputs)
