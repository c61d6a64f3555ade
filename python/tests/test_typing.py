"""``mypy --strict`` checks user code against the package's annotations (py.typed): the
overloads of ``Model.eval`` return ``NDArray[float32]`` or ``NDArray[float64]`` as the dtype
rule says. mypy is installed by tools/test.sh; without it the test fails under CI."""

import os
import pathlib
import subprocess
import sys

import pytest

HERE = pathlib.Path(__file__).resolve().parent


def _mypy(*args):
    try:
        import mypy  # noqa: F401
    except ImportError:
        if os.environ.get("CI"):
            pytest.fail("mypy is not installed (tools/test.sh installs it)")
        pytest.skip("mypy is not installed")
    return subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--no-incremental", "--cache-dir", os.devnull, *args],
        capture_output=True, text=True, timeout=300,
    )


def test_user_code_type_checks_strictly():
    p = _mypy(str(HERE / "typing" / "user_code.py"))
    assert p.returncode == 0, p.stdout + p.stderr


def test_a_wrong_annotation_is_caught():
    # The check can fail: a float32 call annotated float64 is an error.
    bad = HERE / "typing" / "user_code.py"
    text = bad.read_text().replace("assert_type(m.eval(x32), npt.NDArray[np.float32])", "assert_type(m.eval(x32), npt.NDArray[np.float64])")
    p = _mypy("-c", text)
    assert p.returncode == 1 and "[assert-type]" in p.stdout, p.stdout + p.stderr


def test_the_package_type_checks_strictly():
    """The installed package itself (its modules and the native module's stubs) passes
    ``mypy --strict``: the annotations users rely on are consistent with the code."""
    p = _mypy("-p", "fastbrdf")
    assert p.returncode == 0 and "no issues found in" in p.stdout, p.stdout + p.stderr
