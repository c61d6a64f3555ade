"""Every ```python block of README.md and of the book (docs/book/src/**/*.md, and
python/README.md when there is one) runs as pasted: a block that stops working fails here.
The shell blocks run from crates/cli/tests/docs.rs (docs/book/src/testing.md says how)."""

import os
import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
PAGES = [p for p in (ROOT / "README.md", ROOT / "python" / "README.md") if p.exists()] + sorted(
    (ROOT / "docs" / "book" / "src").rglob("*.md")
)


def blocks():
    found = []
    for path in PAGES:
        text = path.read_text(encoding="utf-8")
        for m in re.finditer(r"^```python[ \t]*\n(.*?)^```[ \t]*$", text, re.S | re.M):
            line = text.count("\n", 0, m.start()) + 1
            found.append(pytest.param(path, line, m.group(1), id=f"{path.relative_to(ROOT)}:{line}"))
    return found


def test_the_readme_and_the_book_have_python_blocks():
    pages = {p.name for p in (b.values[0] for b in blocks())}
    assert "README.md" in pages and "python.md" in pages, pages


def test_every_python_fence_is_plain():
    # A ```python block with marks (```python ignore) would not be run by the pattern above.
    for path in PAGES:
        for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if line.startswith("```python"):
                assert line.rstrip() == "```python", f"{path.relative_to(ROOT)}:{n}: {line}"


@pytest.mark.parametrize("path, line, code", blocks())
def test_python_block_runs_as_pasted(path, line, code, tmp_path, monkeypatch):
    # A fresh namespace, in an empty directory (whatever a block writes stays there).
    monkeypatch.chdir(tmp_path)
    exec(compile(code, f"{path.name}:{line}", "exec"), {"__name__": "__docs__"})
    assert os.getcwd() == str(tmp_path)
