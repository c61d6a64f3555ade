"""Every ```python block of the README (and of python/README.md, when there is one) runs as
pasted: a block that stops working fails here."""

import os
import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
READMES = [p for p in (ROOT / "README.md", ROOT / "python" / "README.md") if p.exists()]


def blocks():
    found = []
    for path in READMES:
        text = path.read_text(encoding="utf-8")
        for m in re.finditer(r"^```python[ \t]*\n(.*?)^```[ \t]*$", text, re.S | re.M):
            line = text.count("\n", 0, m.start()) + 1
            found.append(pytest.param(path, line, m.group(1), id=f"{path.relative_to(ROOT)}:{line}"))
    return found


def test_the_readme_has_python_blocks():
    assert len(blocks()) >= 1


@pytest.mark.parametrize("path, line, code", blocks())
def test_python_block_runs_as_pasted(path, line, code, tmp_path, monkeypatch):
    # A fresh namespace, in an empty directory (whatever a block writes stays there).
    monkeypatch.chdir(tmp_path)
    exec(compile(code, f"{path.name}:{line}", "exec"), {"__name__": "__readme__"})
    assert os.getcwd() == str(tmp_path)
