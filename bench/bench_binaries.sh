#!/usr/bin/env bash
# Two builds of restir, the same frames, interleaved in one run (issue 43: no CPU slowdown from one
# frame per algorithm): each integrator at 640x360 on its scene, ROUNDS rounds of OLD then NEW (the
# order alternating each round, so that a drift of the host's speed falls on both), FRAMES frames a
# run; a run's ms/frame is the median of its frames after the first (frame 0 builds what the later
# ones reuse). Prints each run, then per integrator the medians over rounds and NEW / OLD.
#   bench/bench_binaries.sh OLD_RESTIR NEW_RESTIR [ROUNDS] [FRAMES]
# e.g. OLD = a build of the commit before the change in a git worktree (README "Tests and benchmarks", docs/benchmarks.md).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
old="$1"; new="$2"; rounds="${3:-5}"; frames="${4:-5}"
shared="$root/../shared/scenes"
cases=(
  "pt|$shared/cornell-box/scene-v4.pbrt|--spp 4"
  "restir-di|$root/scenes/many-lights.pbrt|--spp 1"
  "restir-gi|$root/scenes/teapot.pbrt|--spp 1"
  "restir-pt|$root/scenes/teapot.pbrt|--spp 1"
  "ssr|$root/scenes/mirror-floor.pbrt|--spp 1"
)
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
# ms/frame of one run: the median of frames 1.. of its --timings CSV.
run() {
  local bin="$1" integrator="$2" scene="$3" args="$4"
  # shellcheck disable=SC2086
  "$bin" render "$scene" --integrator "$integrator" --res 640x360 --frames "$frames" -q -o "$tmp/out.exr" --timings "$tmp/t.csv" $args 2>/dev/null
  awk -F, 'NR > 2 { print $2 }' "$tmp/t.csv" | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2) }'
}
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2) }'; }
printf "%-10s %5s %12s %12s\n" integrator round "old ms" "new ms"
for c in "${cases[@]}"; do
  IFS='|' read -r integrator scene args <<< "$c"
  : > "$tmp/old"; : > "$tmp/new"
  for ((r = 0; r < rounds; ++r)); do
    if ((r % 2 == 0)); then a=$(run "$old" "$integrator" "$scene" "$args"); b=$(run "$new" "$integrator" "$scene" "$args")
    else b=$(run "$new" "$integrator" "$scene" "$args"); a=$(run "$old" "$integrator" "$scene" "$args"); fi
    echo "$a" >> "$tmp/old"; echo "$b" >> "$tmp/new"
    printf "%-10s %5d %12.1f %12.1f\n" "$integrator" "$r" "$a" "$b"
  done
  mo=$(median < "$tmp/old"); mn=$(median < "$tmp/new")
  printf "%-10s  median %9.1f %12.1f   new / old = %.3f\n" "$integrator" "$mo" "$mn" "$(awk -v a="$mo" -v b="$mn" 'BEGIN { print b / a }')"
done
