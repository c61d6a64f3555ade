#!/usr/bin/env bash
# Interleaved wall-clock timing of two `fastbrdf` binaries on the same render, so that the
# shared machine's load hits both alike: OLD, NEW, OLD, NEW, ... RUNS times each, then the
# median of each and their ratio. Times are whole processes (start, render, encode, write),
# in milliseconds, and, when both binaries print it (`fastbrdf render` does since the render
# speed work: "render 0.032 s, encode and write ..."), the render alone; with --gpu, also
# the GPU's draws after its set-up ("draws 0.27 s": what tools/equal_error.py times).
#
# Usage: tools/render_speed.sh OLD_BIN NEW_BIN [RUNS] [-- RENDER_ARGS...]
#   default RUNS 9; default render: the 1024x1024 sphere, pow n=50, 1 sample per pixel, PNG
#   (append `-- ... --out x.exr` etc. to time another scene; --out defaults to a temp .png).
# An old binary: git worktree add /tmp/old REV && (cd /tmp/old && cargo build --release -p
#   fastbrdf-cli) && cp /tmp/old/target/release/fastbrdf /tmp/fastbrdf-old. For the render
#   alone, build the old renderer with the new CLI: in a clean checkout of the new code,
#   `git checkout REV -- crates/render/src`, build, copy the binary, `git checkout HEAD --
#   crates/render/src`.
set -euo pipefail
old=$1 new=$2; shift 2
runs=9
if [[ $# -gt 0 && $1 != -- ]]; then runs=$1; shift; fi
[[ $# -gt 0 && $1 == -- ]] && shift
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
args=("$@")
if [[ ${#args[@]} -eq 0 ]]; then
  args=(--model pow --param n=50 --size 1024x1024 --spp 1)
fi
has_out=0; for a in "${args[@]}"; do [[ $a == --out ]] && has_out=1; done
[[ $has_out == 1 ]] || args+=(--out "$tmp/out.png")
# Appends the wall time (ms) to $1 and the printed render time (ms, if any) to $1.render.
time_ms() {
  local f=$1 s e err
  shift
  s=$(date +%s%N)
  err=$("$@" 2>&1 >/dev/null)
  e=$(date +%s%N)
  echo $(((e - s) / 1000000)) >>"$f"
  sed -nE 's/.*render ([0-9.]+) s.*/\1/p' <<<"$err" | awk '{print $1 * 1000}' >>"$f.render"
  sed -nE 's/.*draws ([0-9.]+) s.*/\1/p' <<<"$err" | awk '{print $1 * 1000}' >>"$f.draws"
}
median() { sort -n | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
"$old" render "${args[@]}" 2>/dev/null; "$new" render "${args[@]}" 2>/dev/null # warm caches
for f in old new; do : >"$tmp/$f"; : >"$tmp/$f.render"; : >"$tmp/$f.draws"; done
for ((i = 0; i < runs; i++)); do
  time_ms "$tmp/old" "$old" render "${args[@]}"
  time_ms "$tmp/new" "$new" render "${args[@]}"
done
echo "fastbrdf render ${args[*]}  ($runs runs each, interleaved)"
report() { # label file
  local mo mn
  mo=$(median <"$tmp/old$2"); mn=$(median <"$tmp/new$2")
  echo "$1 old: $(tr '\n' ' ' <"$tmp/old$2")-> median $mo ms"
  echo "$1 new: $(tr '\n' ' ' <"$tmp/new$2")-> median $mn ms"
  awk -v o="$mo" -v n="$mn" -v l="$1" 'BEGIN {printf "%s speed-up (old / new median): %.2fx\n", l, o / n}'
}
report "process" ""
if [[ -s $tmp/old.render && -s $tmp/new.render ]]; then report "render " .render; fi
if [[ -s $tmp/old.draws && -s $tmp/new.draws ]]; then report "draws  " .draws; fi
