#!/usr/bin/env bash
# The figures a machine with a real GPU gives (docs/book/src/equal-error.md, "On a real GPU"), in one
# prepared run: what the machine is, `fastbrdf bench --gpu --json`, and tools/equal_error.py's
# fastbrdf columns (CPU and GPU renderer; Mitsuba where it is importable) at its --full settings.
#
#   cargo build --release -p fastbrdf-cli
#   tools/gpu_figures.sh OUTDIR [FASTBRDF]
#
# Each step has its own time limit and a failing step does not stop the next: OUTDIR then holds
# its stderr (*.err, *.log) and status.txt its exit code. Nothing here is run by the tests.
set -u
out=${1:?usage: tools/gpu_figures.sh OUTDIR [FASTBRDF]}
fb=${2:-target/release/fastbrdf}
root=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
{
    date -u +%Y-%m-%dT%H:%M:%SZ
    git -C "$root" rev-parse HEAD 2>/dev/null || echo "no git"
    nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv 2>&1 || echo "no nvidia-smi"
    grep -m1 'model name' /proc/cpuinfo
    echo "cores: $(nproc)"
} >"$out/machine.txt"
cat "$out/machine.txt"
status() { echo "$1 rc=$2" | tee -a "$out/status.txt"; }
timeout "${BENCH_LIMIT:-240}" "$fb" bench --gpu --json >"$out/bench-gpu.json" 2>"$out/bench-gpu.err"
status bench "$?"
timeout "${EQUAL_ERROR_LIMIT:-300}" python3 "$root/tools/equal_error.py" --full --fastbrdf "$fb" \
    --out-json "$out/equal-error-gpu.json" >"$out/equal-error.md" 2>"$out/equal-error.log"
status equal_error "$?"
