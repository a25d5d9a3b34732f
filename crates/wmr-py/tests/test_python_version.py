"""The package's Python code, the notebooks and examples/notebook.py need nothing newer
than the oldest Python the package declares (pyproject's requires-python, issue 40):
ruff's target-version and vermin are not available offline, so the check is ast's own.
It parses every file with that version's grammar and refuses what the grammar does not
see: standard-library modules and typing names added later, unguarded (an import in a
`try` whose `except ImportError` has a fallback is fine), `zip(..., strict=)` and
`X | Y` in annotations evaluated at run time (no `from __future__ import annotations`)."""

from __future__ import annotations

import ast
import json
import pathlib
import re
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]
PYPROJECT = REPO / "crates" / "wmr-py" / "pyproject.toml"

# Modules of the standard library by the version that added them (after 3.8).
NEW_MODULES = {"graphlib": (3, 9), "zoneinfo": (3, 9), "tomllib": (3, 11), "wsgiref.types": (3, 11)}
# typing's names by the version that added them (after 3.8).
NEW_TYPING = {
    "Annotated": (3, 9),
    "ParamSpec": (3, 10),
    "Concatenate": (3, 10),
    "TypeAlias": (3, 10),
    "TypeGuard": (3, 10),
    "Self": (3, 11),
    "Never": (3, 11),
    "LiteralString": (3, 11),
    "Required": (3, 11),
    "NotRequired": (3, 11),
    "TypeVarTuple": (3, 11),
    "Unpack": (3, 11),
    "assert_never": (3, 11),
    "assert_type": (3, 11),
    "reveal_type": (3, 11),
    "dataclass_transform": (3, 11),
    "override": (3, 12),
    "TypeIs": (3, 13),
    "ReadOnly": (3, 13),
}


def oldest_python() -> tuple[int, int]:
    """requires-python = ">=3.9" as (3, 9)."""
    m = re.search(r'^requires-python\s*=\s*">=\s*(\d+)\.(\d+)"', PYPROJECT.read_text(), re.M)
    assert m, "pyproject.toml: no requires-python = \">=X.Y\""
    return int(m.group(1)), int(m.group(2))


def sources() -> list[tuple[str, str]]:
    """(name, code) of every module of the package, every notebook's code cells and the
    script notebook; IPython's magics (`%...`, `!...`) left out."""
    out = []
    for p in sorted((REPO / "crates" / "wmr-py" / "python").rglob("*.py")):
        out.append((str(p.relative_to(REPO)), p.read_text()))
    out.append(("examples/notebook.py", (REPO / "examples" / "notebook.py").read_text()))
    for nb in sorted((REPO / "examples" / "notebooks").glob("*.ipynb")):
        cells = [c for c in json.loads(nb.read_text())["cells"] if c["cell_type"] == "code"]
        for i, c in enumerate(cells):
            code = "".join(c["source"])
            code = "\n".join("" if line.lstrip().startswith(("%", "!")) else line for line in code.splitlines())
            out.append((f"{nb.relative_to(REPO)} code cell {i}", code))
    return out


def guarded(tree: ast.AST) -> set[int]:
    """Ids of the import nodes inside a `try` that catches ImportError (or
    ModuleNotFoundError) and so has a fallback."""
    ids = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Try):
            names = set()
            for h in node.handlers:
                types = h.type.elts if isinstance(h.type, ast.Tuple) else [h.type]
                names |= {t.id for t in types if isinstance(t, ast.Name)}
            if names & {"ImportError", "ModuleNotFoundError"}:
                ids |= {id(n) for stmt in node.body for n in ast.walk(stmt)}
    return ids


def problems(code: str, oldest: tuple[int, int]) -> list[str]:
    try:
        tree = ast.parse(code, feature_version=oldest)
    except SyntaxError as e:
        return [f"line {e.lineno}: not Python {oldest[0]}.{oldest[1]} syntax: {e.msg}"]
    out = []
    safe = guarded(tree)
    future_annotations = any(
        isinstance(n, ast.ImportFrom) and n.module == "__future__" and any(a.name == "annotations" for a in n.names)
        for n in tree.body
    )
    for node in ast.walk(tree):
        if isinstance(node, (ast.Import, ast.ImportFrom)) and id(node) not in safe:
            mods = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module or ""]
            for mod in mods:
                need = NEW_MODULES.get(mod)
                if need and need > oldest:
                    out.append(f"line {node.lineno}: imports {mod} (Python {need[0]}.{need[1]}) without a fallback")
            if isinstance(node, ast.ImportFrom) and node.module == "typing":
                for a in node.names:
                    need = NEW_TYPING.get(a.name)
                    if need and need > oldest:
                        out.append(f"line {node.lineno}: typing.{a.name} is Python {need[0]}.{need[1]}")
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "zip":
            if any(k.arg == "strict" for k in node.keywords) and (3, 10) > oldest:
                out.append(f"line {node.lineno}: zip(strict=) is Python 3.10")
        if not future_annotations and (3, 10) > oldest:
            annotations = []
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                args = node.args.posonlyargs + node.args.args + node.args.kwonlyargs
                args += [a for a in (node.args.vararg, node.args.kwarg) if a]
                annotations = [a.annotation for a in args if a.annotation] + ([node.returns] if node.returns else [])
            elif isinstance(node, ast.AnnAssign):
                annotations = [node.annotation]
            for ann in annotations:
                if any(isinstance(n, ast.BinOp) and isinstance(n.op, ast.BitOr) for n in ast.walk(ann)):
                    out.append(f"line {node.lineno}: X | Y in an annotation needs Python 3.10 (or the __future__ import)")
    return out


@pytest.mark.parametrize("name,code", sources(), ids=lambda v: v if len(v) < 80 else "")
def test_code_needs_nothing_newer_than_the_oldest_declared_python(name: str, code: str) -> None:
    oldest = oldest_python()
    found = problems(code, oldest)
    assert not found, f"{name}: " + "; ".join(found)


def test_the_check_finds_what_it_looks_for() -> None:
    """Each rule on a line that breaks it (and the guarded fallback passes)."""
    old = (3, 9)
    assert problems("import tomllib\n", old)
    assert not problems("try:\n    import tomllib\nexcept ModuleNotFoundError:\n    import tomli as tomllib\n", old)
    assert problems("from typing import TypeAlias\n", old)
    assert problems("match x:\n    case 1:\n        pass\n", old)
    assert problems("zip(a, b, strict=True)\n", old)
    assert problems("def f(x: int | None) -> None: ...\n", old)
    assert not problems("from __future__ import annotations\ndef f(x: int | None) -> None: ...\n", old)
    assert oldest_python() <= (sys.version_info.major, sys.version_info.minor)


# The distribution that provides each module the notebooks import (beyond the package's
# own dependency numpy and the standard library).
PROVIDER = {"matplotlib": "matplotlib", "pandas": "pandas", "scipy": "scipy", "distributed": "dask",
            "dask": "dask", "tqdm": "tqdm", "xarray": "xarray", "tomli": "tomli"}


def extras() -> dict:
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.9 and 3.10
        import tomli as tomllib  # type: ignore[no-redef]
    return tomllib.loads(PYPROJECT.read_text())["project"]["optional-dependencies"]


def distribution(requirement: str) -> str:
    """`dask[distributed]`, `tomli; python_version < '3.11'` -> dask, tomli."""
    return re.split(r"[\[;<>=! ]", requirement, maxsplit=1)[0].lower()


def test_the_notebooks_extra_installs_what_the_notebooks_import() -> None:
    """`pip install wmr-py[notebooks]` (and `[all]`) brings every package a notebook
    imports, and pandas, xarray, tqdm, scipy and dask (issue 40)."""
    ex = extras()
    notebooks = {distribution(r) for r in ex["notebooks"]}
    assert {"pandas", "xarray", "tqdm", "scipy", "dask"} <= notebooks, notebooks
    imported = set()
    for name, code in sources():
        if name.startswith("examples/notebooks/"):
            for node in ast.walk(ast.parse(code)):
                if isinstance(node, ast.Import):
                    imported |= {a.name.split(".")[0] for a in node.names}
                elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                    imported.add(node.module.split(".")[0])
    needed = {PROVIDER[m] for m in imported if m in PROVIDER}
    assert needed <= notebooks, f"imported but not in the notebooks extra: {needed - notebooks}"
    # [all]: every optional package, through the other extras.
    everything = {distribution(r) for r in ex["all"]}
    assert everything == {"wmr-py"} and set(re.findall(r"\[(.*)\]", ex["all"][0])[0].split(",")) >= {"plot", "notebooks"}
