"""docs/python.md runs: every ```python block of it is a test, executed as written (each block
on its own, in a fresh namespace, inside a temporary directory). Its asserts are the checks."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

DOC = Path(__file__).resolve().parents[2] / "docs" / "python.md"


def blocks():
    text = DOC.read_text()
    found = []
    heading = "top"
    for m in re.finditer(r"^(#{2,3} .*)$|^```python\n(.*?)^```", text, re.S | re.M):
        if m.group(1):
            heading = m.group(1).lstrip("# ").strip()
        else:
            found.append(pytest.param(m.group(2), id=f"{len(found)}-{re.sub(r'[^A-Za-z0-9]+', '-', heading)[:40]}"))
    return found


def test_the_doc_has_examples():
    assert len(blocks()) >= 4


@pytest.mark.parametrize("code", blocks())
def test_example(code, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    exec(compile(code, str(DOC), "exec"), {"__name__": "__doc_example__"})
