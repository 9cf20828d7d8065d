#!/usr/bin/env bash
# Issue 10: what the viewer loop costs over the bare render. For pt and restir-di on the Cornell
# box at 640x360 (1 spp per frame, the viewer's default), `restir view --bench N` renders N frames
# bare (FrameRenderer and the running mean, as `restir render`) and N through the viewer (worker
# thread, display transform, texture upload, ImGui), alternating five times, in one run, and prints
# ms/frame of both and their ratio (goal: the viewer adds < 5%), at the default redraw budget, then
# pt once more showing every frame (--redraw-budget 1). Runs under xvfb-run (Mesa's software
# OpenGL) when there is no $DISPLAY.
#   bench/bench_viewer.sh [RESTIR_BINARY] [FRAMES]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
restir="${1:-$root/build/bin/restir}"
frames="${2:-30}"
scene="$root/../shared/scenes/cornell-box/scene-v4.pbrt"
[ -f "$scene" ] || scene="$root/scenes/cornell-box.pbrt"
run=()
[ -n "${DISPLAY:-}" ] || run=(xvfb-run -a -s "-screen 0 1600x1000x24")
for run_args in "pt" "restir-di" "pt --redraw-budget 1"; do
  read -r integrator extra <<< "$run_args"
  # shellcheck disable=SC2086
  "${run[@]}" "$restir" view "$scene" --integrator "$integrator" --set film.width=640 --set film.height=360 \
    --bench "$frames" $extra 2>/dev/null
done
