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
# Then the Python package (python/, issues 17 and 29), with no arguments (the whole suite: this
# step runs beside the Rust tests, once every test is built, and prints its output after
# theirs) or with `--python` alone (only this step). It builds a wheel with maturin (from a virtual
# environment target/python-venv that holds maturin) into target/python-wheels/, in cargo's dev
# profile, which reuses what `cargo test` just built; then it makes a fresh virtual environment
# target/python-wheel-venv with no Rust toolchain on PATH, installs the test dependencies from
# PyPI as binary wheels (numpy, pytest, pytest-xdist, mypy, mitsuba, dask[distributed], joblib)
# and the wheel alone from target/python-wheels/ (--no-index), and runs `pytest -n auto
# python/tests` there: one pytest worker per core (on the 2-core machine 96 s against 134 s
# for one worker, the suite warm, one run each).
# FASTBRDF_WHEEL_RELEASE=1 builds the wheel in the release profile instead (the wheel one
# ships). Why not release in CI: on the project's 2-core machine `maturin build --release` from
# an empty target folder took 512 s of CPU (487 user, 25 system; 15.7 min of wall clock at a
# load of 2 to 8 from other builds), over 4 minutes even on two free cores, while CI's budget
# for this step is about 3 minutes; the dev wheel after `cargo test` reuses the workspace's
# crates and compiles only what `cargo test` does not build (pyo3, the numpy bindings and the
# fastbrdf-python crate). The fresh environment's packages took 14 to 35 s to install (pip's
# cache warm, load 6; 57 s with no cache, 431 MB installed). With extra cargo arguments the
# Python step is left out. Under CI a missing piece (python3, a virtual environment, a package
# from PyPI) fails the script; without CI it is skipped with a message.
set -euo pipefail
cd "$(dirname "$0")/.."
# Under CI (a fresh clone, built once), no incremental caches: they cost a from-scratch build
# about a quarter of its time (.ci/run says what was measured). A developer's rebuilds keep them.
if [ -n "${CI:-}" ]; then
    export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"
fi

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
# spirv-opt counts every shader's instructions after an optimising compiler
# (crates/gpu/tests/cost.rs); with CI set a missing spirv-opt fails that test, without CI it is
# skipped with a message.
if ! command -v spirv-opt > /dev/null; then
    echo "test.sh: no spirv-opt: installing spirv-tools (the instruction-count test)" >&2
    if command -v apt-get > /dev/null; then
        apt_install spirv-tools || { $sudo apt-get update -qq > /dev/null && apt_install spirv-tools; } ||
            echo "test.sh: could not install spirv-tools; the instruction-count test will skip (or fail under CI)" >&2
    else
        echo "test.sh: no apt-get; install SPIRV-Tools (spirv-opt) to run the instruction-count test" >&2
    fi
fi
# The Khronos glTF-Validator checks every glTF file the writer makes
# (crates/render/tests/gltf_validator.rs, through tools/gltf_validate.mjs): the npm package
# gltf-validator (one file of compiled Dart, ~0.4 MB, no dependencies), installed into
# target/gltf-validator with Node.js and npm (Debian's nodejs and npm when missing); the test
# finds it through FASTBRDF_GLTF_VALIDATOR. With CI set a missing validator fails that test,
# without CI it is skipped with a message.
gltf_validator_version=2.0.0-dev.3.10
gltf_validator="${FASTBRDF_GLTF_VALIDATOR:-$PWD/target/gltf-validator/node_modules/gltf-validator}"
if [ -z "${FASTBRDF_GLTF_VALIDATOR:-}" ] && { [ ! -e "$gltf_validator/package.json" ] ||
    ! grep -q "\"version\": \"$gltf_validator_version\"" "$gltf_validator/package.json"; }; then
    if ! command -v node > /dev/null || ! command -v npm > /dev/null; then
        echo "test.sh: no node or npm: installing Debian's nodejs and npm (the glTF-Validator test)" >&2
        if command -v apt-get > /dev/null; then
            apt_install nodejs npm || { $sudo apt-get update -qq > /dev/null && apt_install nodejs npm; } ||
                echo "test.sh: could not install nodejs and npm; the glTF-Validator test will skip (or fail under CI)" >&2
        else
            echo "test.sh: no apt-get; install Node.js and npm to run the glTF-Validator test" >&2
        fi
    fi
    if command -v npm > /dev/null; then
        echo "test.sh: installing gltf-validator@$gltf_validator_version into target/gltf-validator" >&2
        npm install --prefix target/gltf-validator --no-audit --no-fund --loglevel=error \
            "gltf-validator@$gltf_validator_version" > /dev/null ||
            echo "test.sh: could not install gltf-validator; the glTF-Validator test will skip (or fail under CI)" >&2
    fi
fi
export FASTBRDF_GLTF_VALIDATOR="$gltf_validator"
if [ -e "$icd" ] && [ -z "${VK_ICD_FILENAMES:-}" ] && [ -z "${VK_DRIVER_FILES:-}" ]; then
    export VK_ICD_FILENAMES="$icd"
fi
export WGPU_BACKEND="${WGPU_BACKEND:-vulkan}"
# What this script makes in the temporary folder goes when it exits, however it exits.
scratch=()
trap 'rm -rf "${scratch[@]}"' EXIT
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
    XDG_RUNTIME_DIR="$(mktemp -d)"
    export XDG_RUNTIME_DIR
    scratch+=("$XDG_RUNTIME_DIR")
fi

# The Python step. Prints why and fails under CI, or skips (returns 0) without CI.
python_missing() {
    if [ -n "${CI:-}" ]; then
        echo "test.sh: $1 (CI: failing)" >&2
        exit 1
    fi
    echo "test.sh: $1; skipping the Python tests" >&2
}

# PATH without the folders that hold a Rust toolchain (cargo, rustc, rustup): the wheel's
# virtual environment is made, filled and tested with it, so nothing there can build Rust.
path_without_rust() {
    local d out="" IFS=:
    for d in $PATH; do
        if [ -z "$d" ] || [ -e "$d/cargo" ] || [ -e "$d/rustc" ] || [ -e "$d/rustup" ]; then continue; fi
        out="${out:+$out:}$d"
    done
    printf '%s' "$out"
}

# Makes the virtual environment $1 with python3 (installing Debian's python3-venv when
# `python3 -m venv` cannot); returns 1 when it cannot.
make_venv() {
    if python3 -m venv "$1" > /dev/null 2>&1; then return 0; fi
    rm -rf "$1"
    echo "test.sh: python3 -m venv failed: installing python3-venv" >&2
    if command -v apt-get > /dev/null; then
        apt_install python3-venv || { $sudo apt-get update -qq > /dev/null && apt_install python3-venv; } || true
    fi
    python3 -m venv "$1" || { rm -rf "$1"; return 1; }
}

python_tests() {
    local build=target/python-venv wheels=target/python-wheels venv=target/python-wheel-venv
    local profile=dev t0=$SECONDS t
    if [ -n "${FASTBRDF_WHEEL_RELEASE:-}" ]; then profile=release; fi
    if ! command -v python3 > /dev/null; then
        python_missing "no python3"
        return 0
    fi
    if [ ! -x "$build/bin/python" ] && ! make_venv "$build"; then
        python_missing "cannot create a virtual environment (python3-venv)"
        return 0
    fi
    if ! "$build/bin/python" -m pip install -q --disable-pip-version-check "maturin>=1.9,<2"; then
        python_missing "cannot install maturin into $build"
        return 0
    fi
    # 1. The wheel, built by maturin with cargo (the dev profile reuses `cargo test`'s artifacts).
    echo "test.sh: maturin build --profile $profile (python/) into $wheels" >&2
    rm -rf "$wheels"
    t=$SECONDS
    "$build/bin/maturin" build --quiet --locked --profile "$profile" -m python/Cargo.toml \
        -i "$build/bin/python" --out "$wheels"
    echo "test.sh: wheel $(cd "$wheels" && ls) built in $((SECONDS - t)) s" >&2
    # 2. A fresh virtual environment with no Rust toolchain on PATH: the test dependencies from
    # PyPI (binary wheels only, no bytecode compiled at install), then the wheel alone from
    # $wheels (--no-index). Nothing can compile there: the wheel is all it takes.
    local norust
    norust="$(path_without_rust)"
    if env PATH="$norust" bash -c 'command -v cargo || command -v rustc' > /dev/null; then
        echo "test.sh: cargo or rustc still on PATH after removing their folders" >&2
        exit 1
    fi
    rm -rf "$venv"
    if ! make_venv "$venv"; then
        python_missing "cannot create a virtual environment (python3-venv)"
        return 0
    fi
    t=$SECONDS
    if ! env -u CARGO -u RUSTC PATH="$norust" "$venv/bin/python" -m pip install -q --no-compile \
        --disable-pip-version-check --only-binary :all: numpy pytest pytest-xdist mypy "mitsuba==3.9.1" "dask[distributed]" joblib; then
        python_missing "cannot install numpy, pytest, pytest-xdist, mypy, mitsuba, dask[distributed] and joblib into $venv"
        return 0
    fi
    env -u CARGO -u RUSTC PATH="$norust" "$venv/bin/python" -m pip install -q --no-compile \
        --disable-pip-version-check --only-binary :all: --no-index --find-links "$wheels" fastbrdf
    echo "test.sh: $venv made with the wheel and its test dependencies in $((SECONDS - t)) s" >&2
    # Mitsuba's llvm_* variants (the plug-in's wavefront tests) need a libLLVM of version 16 or
    # newer that Dr.Jit finds: Debian's libllvm19 (~30 MB), installed when missing. Under CI
    # the llvm tests then fail instead of skipping when none is found (FASTBRDF_NEED_LLVM).
    if ! compgen -G "/usr/lib/*/libLLVM-1[6-9]*.so*" > /dev/null \
        && ! compgen -G "/usr/lib/*/libLLVM-[2-9][0-9]*.so*" > /dev/null \
        && [ -z "${DRJIT_LIBLLVM_PATH:-}" ] && command -v apt-get > /dev/null; then
        echo "test.sh: no libLLVM 16+ for Mitsuba's llvm variants: installing libllvm19" >&2
        apt_install libllvm19 || { $sudo apt-get update -qq > /dev/null && apt_install libllvm19; } ||
            echo "test.sh: could not install libllvm19; Mitsuba's llvm tests will skip (or fail under CI)" >&2
    fi
    local need_llvm=""
    if [ -n "${CI:-}" ]; then need_llvm=1; fi
    # 3. The tests, against the installed wheel (not python/fastbrdf: it is not on sys.path).
    env -u CARGO -u RUSTC PATH="$PWD/$venv/bin:$norust" "$venv/bin/python" -c \
        'import fastbrdf, sys; f = fastbrdf.__file__; assert "/python-wheel-venv/" in f, f'
    t=$SECONDS
    env -u CARGO -u RUSTC PATH="$PWD/$venv/bin:$norust" FASTBRDF_NEED_LLVM="$need_llvm" \
        FASTBRDF_WHEEL_PROFILE="$profile" \
        "$venv/bin/python" -m pytest -q -p no:cacheprovider -n auto python/tests
    echo "test.sh: pytest in $((SECONDS - t)) s; the Python step in $((SECONDS - t0)) s" >&2
}

if [ "$#" -eq 1 ] && [ "$1" = "--python" ]; then
    python_tests
    exit 0
fi
if [ "$#" -ne 0 ]; then
    cargo test --workspace --locked "$@"
    exit 0
fi
# The whole suite: build every test first, then run the Rust tests and the Python step side by
# side. The Rust tests leave a core idle for minutes at a time (a shader compiling on one core,
# a browser test waiting on its page: 19% of the two cores idle over the 18 minutes, vmstat,
# the 2-core machine), which the wheel's build and pytest fill. Cargo holds its build lock
# only while building, so the wheel's `maturin build` in the same target folder does not wait
# for the tests; it compiles only the Python crate and what `cargo test` did not build. The
# Python step's output is kept in a file and printed after the Rust tests; either failing
# fails the script.
cargo test --workspace --locked --no-run
# The tests' temporary folder is a fresh one, removed at the end: what a test leaves there
# (it must not: "nothing left behind") is named below, and fails the run under CI.
tests_tmp="$(mktemp -d)"
scratch+=("$tests_tmp")
export TMPDIR="$tests_tmp"
python_log="$(mktemp)" rust_log="$(mktemp)"  # in $tests_tmp
# The wheel's build waits until `cargo test` has checked that every test is built and runs
# the first binary (its first "Running" line): the two must not queue on the build lock.
(
    while ! grep -q "Running" "$rust_log" && [ ! -e "$rust_log.done" ]; do sleep 1; done
    python_tests
) > "$python_log" 2>&1 &
python_pid=$!
rust_status=0
cargo test --workspace --locked 2> >(tee "$rust_log" >&2) || rust_status=$?
echo "$rust_status" > "$rust_log.done"
python_status=0
wait "$python_pid" || python_status=$?
echo "test.sh: the Python step, which ran beside the Rust tests:" >&2
cat "$python_log" >&2
rm -f "$python_log" "$rust_log" "$rust_log.done"
# pytest keeps its own recent folders (pytest-of-USER) and dask its lock files
# (dask-scratch-space) by design; anything else was left by a test.
left_status=0
left="$(find "$tests_tmp" -mindepth 1 -maxdepth 1 ! -name 'pytest-of-*' ! -name 'dask-scratch-space' -printf '%f\n' | sort || true)"
if [ -n "$left" ]; then
    echo "test.sh: the tests left these in the temporary folder (they must remove what they make):" >&2
    echo "$left" | sed 's/^/  /' >&2
    if [ -n "${CI:-}" ]; then left_status=1; fi
fi
if [ "$rust_status" -ne 0 ] || [ "$python_status" -ne 0 ] || [ "$left_status" -ne 0 ]; then
    # Kept for a look: a failing test keeps its folder there (and names it).
    keep=()
    for f in "${scratch[@]}"; do [ "$f" = "$tests_tmp" ] || keep+=("$f"); done
    scratch=("${keep[@]}")
    echo "test.sh: the tests' temporary folder is kept: $tests_tmp" >&2
    echo "test.sh: failed (cargo test: exit $rust_status; the Python step: exit $python_status; left files: $left_status)" >&2
    exit 1
fi
