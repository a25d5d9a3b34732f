"""examples/notebooks/*.ipynb run top to bottom on small settings (issue 14,
WMR_NOTEBOOK_QUICK=1: tune_gains' small budget), and are stored with the outputs of their
full settings (issue 40: a reader sees the figures before running anything), written by
`scripts/run-notebooks`, which records the hash of the code cells they came from."""

from __future__ import annotations

import hashlib
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


def code_sha256(nb: dict) -> str:
    """scripts/run-notebooks' hash: every code cell's source, in order, NUL-separated."""
    h = hashlib.sha256()
    for cell in nb["cells"]:
        if cell["cell_type"] == "code":
            source = cell["source"]
            h.update(("".join(source) if isinstance(source, list) else source).encode())
            h.update(b"\0")
    return h.hexdigest()


@pytest.mark.parametrize("name", ["paper.ipynb", "tune_gains.ipynb"])
def test_notebook_is_stored_with_the_outputs_of_its_code(name: str) -> None:
    nb = json.loads((NOTEBOOKS / name).read_text())
    stored = nb["metadata"].get("wmr", {}).get("code_sha256")
    assert stored == code_sha256(nb), (
        f"{name}: its code changed since its outputs were stored: run scripts/run-notebooks {name}"
    )
    code = [c for c in nb["cells"] if c["cell_type"] == "code"]
    # Every cell ran, in order, and none failed.
    assert [c["execution_count"] for c in code] == list(range(1, len(code) + 1))
    assert not [o for c in code for o in c["outputs"] if o.get("output_type") == "error"]
    assert [o for c in code for o in c["outputs"] if "image/png" in o.get("data", {})], f"{name}: no figure stored"
