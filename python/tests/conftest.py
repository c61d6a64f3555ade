"""Shared fixtures: the CLI binary, to compare the package with `fastbrdf` itself."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def cli():
    """Runs the `fastbrdf` binary (FASTBRDF_BIN, else target/debug/fastbrdf, which
    tools/test.sh's `cargo test` builds): returns (returncode, stdout, stderr). Missing: the
    test is skipped, except under CI, where it fails."""
    path = pathlib.Path(os.environ.get("FASTBRDF_BIN", ROOT / "target" / "debug" / "fastbrdf"))
    if not path.exists():
        msg = f"no fastbrdf binary at {path} (run `cargo build -p fastbrdf-cli` or set FASTBRDF_BIN)"
        if os.environ.get("CI"):
            pytest.fail(msg)
        pytest.skip(msg)

    def run(*args, stdin=""):
        p = subprocess.run([str(path), *args], input=stdin, capture_output=True, text=True)
        return p.returncode, p.stdout, p.stderr

    return run
