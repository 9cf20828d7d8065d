#!/usr/bin/env bash
# The main job: installs what is missing, builds the `restir` binary (only it: scripts/test.sh builds
# the tests and benchmarks), renders the default scenes into out/ and runs the default study.
source "$(dirname "$0")/common.sh"
START=$SECONDS
install_missing_packages
# The CUDA backend only for a GPU this machine has (its own architecture, not three), and none where
# there is no GPU: compiling kernels nobody can run was most of a fresh machine's wait.
if gpu_present && command -v nvcc >/dev/null 2>&1; then
  echo "building the CUDA backend for this machine's GPU: $(nvidia-smi -L | head -n 1)"
  configure "$ROOT/build" -DRESTIR_CUDA=ON -DCMAKE_CUDA_ARCHITECTURES=native
else
  echo "no NVIDIA GPU here (or no nvcc): building without the CUDA backend (render.backend=cuda will say so)"
  configure "$ROOT/build" -DRESTIR_CUDA=OFF
fi
cmake --build "$ROOT/build" -j "$(nproc)" --target restir
echo "built build/bin/restir in $((SECONDS - START)) s"
OUT="${OUT:-$ROOT/out}"
mkdir -p "$OUT"
R="$ROOT/build/bin/restir"
SHARED="$ROOT/../shared/scenes"
render() {  # name scene [options...]
  local name="$1" scene="$2"
  shift 2
  echo "== $name"
  "$R" render "$scene" -o "$OUT/$name.exr" --png "$OUT/$name.png" "$@"
}
# Small and quick (seconds each): a first look at every scene, and what ReSTIR is for, a sequence of
# frames at 1 sample per pixel each, beside the path tracer at the same frame time or more.
render cornell-box "$SHARED/cornell-box/scene-v4.pbrt" --res 256x256 --spp 16 --set path.max_depth=8
render cornell-box-restir-pt "$SHARED/cornell-box/scene-v4.pbrt" --res 256x256 --integrator restir-pt --spp 1 --frames 16 --set path.max_depth=8
render veach-mis "$SHARED/veach-mis/scene-v4.pbrt" --res 320x180 --spp 16
render furnace "$SHARED/furnace.pbrt" --spp 16 --set path.max_depth=65
for s in cornell-box many-lights teapot ajar-door env-object; do
  [ -f "$ROOT/scenes/$s.pbrt" ] && render "own-$s" "$ROOT/scenes/$s.pbrt" --res 320x180 --spp 8
done
# The default study (studies/equal-time.json, about two minutes on two cores): ReSTIR PT's shift
# mappings against the path tracer at equal frames and at equal time on the glossy teapots, large
# enough that its answer holds (its verdict: docs/results/equal-time/RESULTS.md; a test checks the
# conclusion). `restir study --list` lists the thesis' figures.
"$R" study equal-time --out "$OUT/study-equal-time"
echo "done in $((SECONDS - START)) s: images in $OUT"
echo "study report: $OUT/study-equal-time/report.html"
