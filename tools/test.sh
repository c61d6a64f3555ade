#!/usr/bin/env bash
# The README's test command: every test of the workspace, GPU tests included.
#
# The GPU tests need a Vulkan driver. Without one (CI, servers), this installs Mesa's
# software driver, lavapipe (Debian's mesa-vulkan-drivers, ~90 MB, a few seconds), and points
# wgpu at it, so the tests run the same everywhere. To test a real GPU instead, set
# VK_ICD_FILENAMES (or WGPU_BACKEND) yourself; this script leaves them alone when set.
# With CI set, a missing GPU adapter fails the GPU tests; without CI they are skipped with a
# message. The end-to-end test of `fastbrdf view` (crates/cli/tests/view.rs) needs a headless
# Chromium: this installs Debian's chromium when none is found (~100 MB with its libraries);
# with CI set a missing Chromium fails that test, without CI it is skipped with a message.
# Extra arguments go to `cargo test` (e.g. `tools/test.sh -p fastbrdf-gpu`).
set -euo pipefail
cd "$(dirname "$0")/.."

sudo=""
if [ "$(id -u)" -ne 0 ] && command -v sudo > /dev/null; then sudo="sudo"; fi
apt_install() {
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$@" > /dev/null
}

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
if [ -e "$icd" ] && [ -z "${VK_ICD_FILENAMES:-}" ] && [ -z "${VK_DRIVER_FILES:-}" ]; then
    export VK_ICD_FILENAMES="$icd"
fi
export WGPU_BACKEND="${WGPU_BACKEND:-vulkan}"
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
    XDG_RUNTIME_DIR="$(mktemp -d)"
    export XDG_RUNTIME_DIR
fi
exec cargo test --workspace --locked "$@"
