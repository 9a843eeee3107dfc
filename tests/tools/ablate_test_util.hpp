#pragma once
// Shared by the tests of `omnidso ablate`: a shell script standing in for `omnidso run`
// (--omnidso), so that successes, failures and resuming are known exactly, and file helpers.

#include <algorithm>
#include <fstream>
#include <iterator>
#include <string>

namespace omnidso::test {

// Writes summary.json like `omnidso run`: RMSE 0.01 × (seed + 1); pinhole-crop:90 with
// N_f 3 exits with status 3; native N_f 3 with seed 1 loses tracking (two segments).
inline constexpr const char* kFakeRun = R"(#!/bin/sh
dataset="$2"; shift 2
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out="$2"; shift ;;
    --camera-model) model="$2"; shift ;;
    --keyframes) kf="$2"; shift ;;
    --seed) seed="$2"; shift ;;
  esac
  shift
done
echo "$model $kf $seed" >> "$(dirname "$0")/calls.txt"
cp "$dataset/groundtruth.txt" "$out/keyframes.txt"
if [ "$model" = "pinhole-crop:90" ] && [ "$kf" = 3 ]; then echo "omnidso: error: fake failure" >&2; exit 3; fi
segments=1
if [ "$model" = native ] && [ "$kf" = 3 ] && [ "$seed" = 1 ]; then segments=2; fi
cat > "$out/summary.json" <<EOF
{"initialized": true, "counts": {"segments": $segments}, "events": [],
 "timing": {"tracking_ms_per_frame": {"mean": 10}, "mapping_ms_per_keyframe": {"mean": 100}},
 "ate": {"keyframe_ate": {"rmse_m": 0.0$((seed + 1)), "rmse_percent_of_path": 1.5}}}
EOF
)";

inline std::string readFile(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline size_t lineCount(const std::string& path) {
  const std::string text = readFile(path);
  return static_cast<size_t>(std::count(text.begin(), text.end(), '\n'));
}

}  // namespace omnidso::test
