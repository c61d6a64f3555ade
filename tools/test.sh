#!/usr/bin/env bash
# The README's test command: every test of the workspace, GPU tests included.
#
# The GPU tests need a Vulkan driver. Without one (CI, servers), this installs Mesa's
# software driver, lavapipe (Debian's mesa-vulkan-drivers, ~90 MB, a few seconds), and points
# wgpu at it, so the tests run the same everywhere. To test a real GPU instead, set
# VK_ICD_FILENAMES (or WGPU_BACKEND) yourself; this script leaves them alone when set.
# With CI set, a missing GPU adapter fails the GPU tests; without CI they are skipped with a
# message. The end-to-end test of `fastbrdf view` (crates/cli/tests/view_page.rs) needs a headless
# Chromium: this installs Debian's chromium when none is found (~100 MB with its libraries);
# with CI set a missing Chromium fails that test, without CI it is skipped with a message.
# Extra arguments go to `cargo test` (e.g. `tools/test.sh -p fastbrdf-gpu`).
#
# Then the Python package (python/, issue 17): with no arguments (the whole suite) or with
# `--python` alone (only this step), it makes a virtual environment target/python-venv if
# missing (installing Debian's python3-venv when `python3 -m venv` cannot), installs maturin,
# pytest and numpy into it, `pip install ./python` (in cargo's dev profile, so it reuses what
# `cargo test` just built; a plain `pip install ./python` builds the release profile), and
# runs `pytest python/tests`. With extra cargo arguments the Python step is left out. Under CI
# a missing piece (python3, the venv, a package) fails the script; without CI it is skipped
# with a message.
set -euo pipefail
cd "$(dirname "$0")/.."

sudo=""
if [ "$(id -u)" -ne 0 ] && command -v sudo > /dev/null; then sudo="sudo"; fi
apt_install() {
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$@" > /dev/null
}

# nv-flip-sys (the FLIP metric) and the analysis crate's C peers compile C++ and C: a machine
# with Rust but no C++ compiler gets Debian's build-essential before anything is built.
if ! command -v c++ > /dev/null || ! command -v cc > /dev/null; then
    echo "test.sh: no C/C++ compiler: installing build-essential" >&2
    if command -v apt-get > /dev/null; then
        apt_install build-essential || { $sudo apt-get update -qq > /dev/null && apt_install build-essential; } || {
            echo "test.sh: could not install build-essential; the build needs a C++ compiler" >&2
            exit 1
        }
    else
        echo "test.sh: no apt-get; install a C and C++ compiler (the build needs them)" >&2
        exit 1
    fi
fi

if [ -z "${FASTBRDF_BROWSER:-}" ] && ! command -v chromium > /dev/null &&
    ! command -v chromium-browser > /dev/null && ! command -v google-chrome > /dev/null; then
    echo "test.sh: no Chromium: installing Debian's chromium (fastbrdf view's end-to-end test)" >&2
    if command -v apt-get > /dev/null; then
        apt_install chromium || { $sudo apt-get update -qq > /dev/null && apt_install chromium; } ||
            echo "test.sh: could not install chromium; the view end-to-end test will skip (or fail under CI)" >&2
    else
        echo "test.sh: no apt-get; install Chromium (or set FASTBRDF_BROWSER) to run the view end-to-end test" >&2
    fi
fi

icd="/usr/share/vulkan/icd.d/lvp_icd.$(uname -m).json"
if [ ! -e "$icd" ]; then
    echo "test.sh: no lavapipe ($icd): installing mesa-vulkan-drivers" >&2
    if command -v apt-get > /dev/null; then
        apt_install mesa-vulkan-drivers || { $sudo apt-get update -qq > /dev/null && apt_install mesa-vulkan-drivers; } ||
            echo "test.sh: could not install mesa-vulkan-drivers; GPU tests will skip (or fail under CI)" >&2
    else
        echo "test.sh: no apt-get; install a Vulkan driver to run the GPU tests" >&2
    fi
fi
# glslang's HLSL front end compiles every HLSL export (crates/gpu/tests/hlsl_glslang.rs); with
# CI set a missing glslangValidator fails that test, without CI it is skipped with a message.
if ! command -v glslangValidator > /dev/null; then
    echo "test.sh: no glslangValidator: installing glslang-tools (the HLSL export test)" >&2
    if command -v apt-get > /dev/null; then
        apt_install glslang-tools || { $sudo apt-get update -qq > /dev/null && apt_install glslang-tools; } ||
            echo "test.sh: could not install glslang-tools; the HLSL export test will skip (or fail under CI)" >&2
    else
        echo "test.sh: no apt-get; install glslang (glslangValidator) to run the HLSL export test" >&2
    fi
fi
if [ -e "$icd" ] && [ -z "${VK_ICD_FILENAMES:-}" ] && [ -z "${VK_DRIVER_FILES:-}" ]; then
    export VK_ICD_FILENAMES="$icd"
fi
export WGPU_BACKEND="${WGPU_BACKEND:-vulkan}"
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
    XDG_RUNTIME_DIR="$(mktemp -d)"
    export XDG_RUNTIME_DIR
fi

# The Python step. Prints why and fails under CI, or skips (returns 0) without CI.
python_missing() {
    if [ -n "${CI:-}" ]; then
        echo "test.sh: $1 (CI: failing)" >&2
        exit 1
    fi
    echo "test.sh: $1; skipping the Python tests" >&2
}

python_tests() {
    local venv=target/python-venv
    if ! command -v python3 > /dev/null; then
        python_missing "no python3"
        return 0
    fi
    if [ ! -x "$venv/bin/python" ]; then
        if ! python3 -m venv "$venv" > /dev/null 2>&1; then
            rm -rf "$venv"
            echo "test.sh: python3 -m venv failed: installing python3-venv" >&2
            if command -v apt-get > /dev/null; then
                apt_install python3-venv || { $sudo apt-get update -qq > /dev/null && apt_install python3-venv; } || true
            fi
            if ! python3 -m venv "$venv"; then
                rm -rf "$venv"
                python_missing "cannot create a virtual environment (python3-venv)"
                return 0
            fi
        fi
    fi
    if ! "$venv/bin/python" -m pip install -q --disable-pip-version-check "maturin>=1.9,<2" pytest numpy; then
        python_missing "cannot install maturin, pytest and numpy into $venv"
        return 0
    fi
    echo "test.sh: pip install ./python (dev profile) and pytest python/tests" >&2
    MATURIN_PEP517_ARGS="--profile dev" "$venv/bin/python" -m pip install -q --disable-pip-version-check \
        --force-reinstall --no-deps ./python
    "$venv/bin/python" -m pytest -q -p no:cacheprovider python/tests
}

if [ "$#" -eq 1 ] && [ "$1" = "--python" ]; then
    python_tests
    exit 0
fi
cargo test --workspace --locked "$@"
if [ "$#" -eq 0 ]; then
    python_tests
fi
