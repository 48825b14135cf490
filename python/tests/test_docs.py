"""docs/python.md runs: every ```python block of it is a test, executed as written (each block
on its own, in a fresh namespace, inside a temporary directory). Its asserts are the checks."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

DOC = Path(__file__).resolve().parents[2] / "docs" / "python.md"


def blocks():
    found, heading, code = [], "top", None
    for number, line in enumerate(DOC.read_text().splitlines(keepends=True), start=1):
        if code is not None:
            if line.startswith("```"):
                slug = re.sub(r"[^A-Za-z0-9]+", "-", heading)[:40].strip("-")
                found.append(pytest.param("".join(code), id=f"{len(found)}-{slug}"))
                code = None
            else:
                code.append(line)
        elif line.startswith("```python"):
            code = ["\n"] * number  # so that a traceback gives the line of docs/python.md
        elif line.startswith("## "):
            heading = line[3:].strip()
    return found


def test_the_doc_has_examples():
    assert len(blocks()) >= 4


@pytest.mark.parametrize("code", blocks())
def test_example(code, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    exec(compile(code, str(DOC), "exec"), {"__name__": "__doc_example__"})
