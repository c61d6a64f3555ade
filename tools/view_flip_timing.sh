#!/usr/bin/env bash
# Time to the pictures and to the full metrics (RMSE, PSNR, FLIP) of the explorer's full
# picture, two `fastbrdf view` binaries side by side, interleaved (issue 30):
#   tools/view_flip_timing.sh OLD_BINARY NEW_BINARY [REPS]
# OLD: /api/render computes FLIP before answering (pictures and metrics arrive together).
# NEW: /api/render?flip=later answers with the pictures, RMSE and PSNR, then /api/flip?job=ID
#      answers FLIP (the page's way); also flip=wait (one request, FLIP from the pool).
# Scenes: the sphere and the embedded face (--mesh face), one model (flog, n=100; MODELS=a,b,c
# for others) against its reference (pow), as the page opens, at the page's full size (512 x 512, 2 x 2 samples) and
# the largest (1024 x 1024, 4 x 4; SIZES=512x2 for the first only). Prints the median
# seconds over REPS (default 3) of each, and every run's.
set -euo pipefail
old=$1 new=$2 reps=${3:-3}
port_old=${PORT_OLD:-8751} port_new=${PORT_NEW:-8752}
"$old" view --port "$port_old" --mesh face 2>/dev/null &
pid_old=$!
"$new" view --port "$port_new" --mesh face 2>/dev/null &
pid_new=$!
trap 'kill $pid_old $pid_new 2>/dev/null' EXIT
for p in "$port_old" "$port_new"; do
  curl -s --retry 30 --retry-delay 1 --retry-connrefused -o /dev/null "http://127.0.0.1:$p/"
done
q="models=${MODELS:-flog}&ref=pow&n=100&theta=30&light=0.5,0.7,0.6"
t() { curl -s -o "$2" -w '%{time_total}' "$1"; }
out=$(mktemp -d)
for rep in $(seq "$reps"); do
  for mesh in sphere mesh; do
    for ss in $(echo "${SIZES:-512x2,1024x4}" | tr ',x' '  ' | xargs -n2 | tr ' ' 'x'); do
      set -- ${ss/x/ }
      base="$q&mesh=$mesh&size=$1&spp=$2"
      key="$mesh ${1}x$1 ${2}x$2"
      # Alternate which server goes first.
      order=$([ $((rep % 2)) = 1 ] && echo "old new" || echo "new old")
      for who in $order; do
        if [ "$who" = old ]; then
          a=$(t "http://127.0.0.1:$port_old/api/render?$base" "$out/o.json")
          echo "$key|old: pictures|$a" >> "$out/rows"
          echo "$key|old: metrics|$a" >> "$out/rows"
        else
          a=$(t "http://127.0.0.1:$port_new/api/render?$base&flip=later" "$out/n.json")
          job=$(grep -o '"flip_job":[0-9]*' "$out/n.json" | cut -d: -f2)
          b=$(t "http://127.0.0.1:$port_new/api/flip?job=$job" "$out/f.json")
          grep -q '"flip":[0-9]' "$out/f.json"
          echo "$key|new: pictures|$a" >> "$out/rows"
          echo "$key|new: metrics|$(echo "$a + $b" | bc -l)" >> "$out/rows"
          c=$(t "http://127.0.0.1:$port_new/api/render?$base&flip=wait" "$out/w.json")
          echo "$key|new, flip=wait: all|$c" >> "$out/rows"
        fi
      done
    done
  done
done
echo "scene | what | median s (of $reps) | all"
cut -d'|' -f1,2 "$out/rows" | awk '!seen[$0]++' | while IFS= read -r key; do
  vals=$(grep -F "$key|" "$out/rows" | cut -d'|' -f3 | sort -g)
  n=$(echo "$vals" | wc -l)
  med=$(echo "$vals" | awk -v n="$n" '{ v[NR] = $1 } END { printf "%.3f", n % 2 ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2 }')
  echo "$key | $med | $(echo $vals)"
done
rm -r "$out"
