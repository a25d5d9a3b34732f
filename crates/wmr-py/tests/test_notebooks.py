"""examples/notebooks/*.ipynb run top to bottom on small settings (issue 14,
WMR_NOTEBOOK_QUICK=1: tune_gains' small budget), stored without outputs (the full
settings take minutes to a quarter of an hour: their outputs are not stored)."""

from __future__ import annotations

import json
import os
import time

import pytest

from conftest import REPO

NOTEBOOKS = REPO / "examples" / "notebooks"


@pytest.mark.parametrize("name", ["paper.ipynb", "tune_gains.ipynb"])
def test_notebook_runs(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    for dep in ("matplotlib", "pandas", "scipy", "distributed"):
        pytest.importorskip(dep)
    monkeypatch.setenv("WMR_NOTEBOOK_QUICK", "1")
    nb = nbformat.read(NOTEBOOKS / name, as_version=4)
    t0 = time.perf_counter()
    nbclient.NotebookClient(nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(NOTEBOOKS)}}).execute()
    elapsed = time.perf_counter() - t0
    print(f"{name}: {elapsed:.1f} s")
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", []) if o.get("output_type") == "error"]
    assert not errors
    # The progress bars draw without tqdm.auto's "IProgress not found" warning where
    # ipywidgets is missing (the test venv has none): a text bar instead (issue 40).
    texts = [o.get("text", "") for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
    assert not [t for t in texts if "IProgress" in t], texts
    # Figures were drawn.
    images = [o for c in nb.cells for o in c.get("outputs", []) if "image/png" in o.get("data", {})]
    assert images, "no figure"


@pytest.mark.parametrize("name", ["paper.ipynb", "tune_gains.ipynb"])
def test_notebook_is_stored_without_outputs(name: str) -> None:
    nb = json.loads((NOTEBOOKS / name).read_text())
    for cell in nb["cells"]:
        if cell["cell_type"] == "code":
            assert cell["outputs"] == [] and cell["execution_count"] is None
