#!/usr/bin/env bash
# The soak of docs/performance.md ("Reliability"): a FRAMES-frame run (default 12 000) of the
# long procedural sequence against a 500-frame run of its beginning. Prints both peak
# resident sizes and, from timing.csv, the mean time per frame (tracking + search +
# mapping) over the first and the last thousand frames.
# Usage: tools/soak.sh BUILD_DIR WORK_DIR [FRAMES]
set -euo pipefail
build=${1:-build}
work=${2:-$build/soak}
frames=${3:-12000}
omnidso="$build/tools/omnidso"
[ -x "$omnidso" ] || { echo "soak: $omnidso is missing; run 'make' first" >&2; exit 1; }
mkdir -p "$work"

# The procedural motion's waves and turns are drawn from the seed in time order, so the
# 500-frame sequence is the long one's beginning.
for n in 500 "$frames"; do
  [ -f "$work/seq$n/times.txt" ] ||
    "$omnidso" synth --preset room185_long --frames "$n" --out "$work/seq$n" --quiet
  rm -rf "$work/out$n"
  /usr/bin/time -v "$omnidso" run "$work/seq$n" --out "$work/out$n" --quiet 2> "$work/time$n.txt"
  echo "$n frames: peak RSS $(awk '/Maximum resident/ {print $6 / 1024}' "$work/time$n.txt") MB," \
       "wall $(awk '/Elapsed/ {print $8}' "$work/time$n.txt")"
done
awk -F, -v n="$frames" 'NR > 1 {
    t = $6 + $7 + $8
    if ($1 < 1000) { a += t; na++ }
    if ($1 >= n - 1000) { b += t; nb++ }
  }
  END { printf "per frame: first 1000 %.1f ms, last 1000 %.1f ms (ratio %.3f)\n",
        a / na, b / nb, (b / nb) / (a / na) }' "$work/out$frames/timing.csv"
