"""Docs as tests for Python (issue 27): every ```python block of README.md, docs/*.md and
the READMEs under examples/, benches/, firmware/ and crates/ runs, in a fresh folder
holding a copy of examples/ and robots/, the blocks of one document in order in one
namespace. A block followed at once by a ```text block must print that text (a line
``...`` stands for any lines, ``[..]`` within a line for any text). The shell commands
of the same documents are crates/wmr-cli/tests/docs_commands.rs's, with the same markers:
a block after ``<!-- docs-test: long -->`` or ``<!-- docs-test: hardware -->`` runs with
WMR_LONG_TESTS=1 only, and is otherwise reported as a skip, never passed silently.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
LONG = os.environ.get("WMR_LONG_TESTS") == "1"


def documents() -> list[str]:
    out = subprocess.run(["git", "-C", str(ROOT), "ls-files", "*.md"], capture_output=True, text=True, check=True)
    docs = []
    for p in out.stdout.split():
        if p == "README.md" or (p.startswith("docs/") and p.count("/") == 1):
            docs.append(p)
        elif p.split("/")[0] in ("examples", "benches", "firmware", "crates") and p.endswith("/README.md"):
            docs.append(p)
    return sorted(docs)


def blocks(text: str) -> list[tuple[int, bool, str, list[str] | None]]:
    """(line, long, code, expected output or None) of each python block."""
    lines = text.split("\n")
    out = []
    i, marked = 0, False
    while i < len(lines):
        s = lines[i].strip()
        if s.startswith("<!-- docs-test:"):
            marked = True
            i += 1
            continue
        if not s.startswith("```"):
            if s:
                marked = False
            i += 1
            continue
        tag, start = s[3:].strip(), i
        body = []
        i += 1
        while i < len(lines) and not lines[i].strip().startswith("```"):
            body.append(lines[i])
            i += 1
        i += 1
        long, marked = marked, False
        if tag != "python":
            continue
        expected = None
        if i < len(lines) and lines[i].strip() == "```text":
            j = i + 1
            expected = []
            while j < len(lines) and not lines[j].strip().startswith("```"):
                expected.append(lines[j])
                j += 1
            i = j + 1
        out.append((start + 1, long, "\n".join(body), expected))
    return out


def line_matches(pattern: str, actual: str) -> bool:
    regex = ".*".join(re.escape(p) for p in pattern.split("[..]"))
    return re.fullmatch(regex, actual) is not None


def lines_match(expected: list[str], actual: list[str]) -> bool:
    if not expected:
        return not actual
    head, rest = expected[0], expected[1:]
    if head.strip() == "...":
        return any(lines_match(rest, actual[k:]) for k in range(len(actual) + 1))
    return bool(actual) and line_matches(head.rstrip(), actual[0].rstrip()) and lines_match(rest, actual[1:])


DOCS = [(d, b) for d in documents() for b in blocks((ROOT / d).read_text())]


@pytest.fixture(scope="module")
def fresh(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("docs")
    for sub in ("examples", "robots"):
        shutil.copytree(ROOT / sub, d / sub)
    return d


NAMESPACES: dict = {}


@pytest.mark.parametrize("doc,block", DOCS, ids=[f"{d}:{b[0]}" for d, b in DOCS])
def test_python_block_runs_and_prints_what_the_doc_shows(doc: str, block: tuple, fresh: Path, monkeypatch) -> None:
    line, long, code, expected = block
    if long and not LONG:
        pytest.skip(f"{doc}:{line} is marked long or hardware: WMR_LONG_TESTS=1 runs it")
    monkeypatch.chdir(fresh)
    ns = NAMESPACES.setdefault(doc, {"__name__": "__docs__"})
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        exec(compile(code, f"{doc}:{line}", "exec"), ns)
    if expected is not None:
        printed = buf.getvalue().rstrip("\n").split("\n")
        assert lines_match(expected, printed), (
            f"{doc}:{line} printed something else than the doc says.\nthe doc:\n"
            + "\n".join(expected)
            + "\nit printed:\n"
            + "\n".join(printed)
        )


def test_the_matcher_matches_what_it_says() -> None:
    assert lines_match(["a [..] c"], ["a b c"])
    assert not lines_match(["a [..] c"], ["a b d"])
    assert lines_match(["a", "...", "z"], ["a", "b", "z"])
    assert not lines_match(["a", "z"], ["a", "b", "z"])
