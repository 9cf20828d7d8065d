#!/usr/bin/env bash
# Issue 16's one prepared command for a machine with an NVIDIA GPU: builds the CUDA backend, runs
# restir_gpu_tests (CPU and CUDA backends agree) and bench_gpu (1920x1080), the resolution and
# equal-time studies on the GPU (run_gpu_studies), and writes a results file. Meant to finish in
# under 10 minutes on one H200 (the studies at most 2 x GPU_CHECK_STUDY_TIMEOUT of it).
#
#   scripts/gpu-check.sh [RESULTS]
#       on a GPU machine with this project's Debian packages (installs what is missing): build in
#       build-gpu/ for the GPU found (CMAKE_CUDA_ARCHITECTURES=native), test, benchmark.
#   scripts/gpu-check.sh --bundle FILE.tar.xz
#       on a build machine without a GPU: build, then pack restir_gpu_tests and bench_gpu with every
#       shared library they load (the dynamic loader and libc included, the CUDA driver excluded)
#       and the scenes they read, for a GPU machine that lacks the build's packages.
#   scripts/gpu-check.sh --from-bundle FILE.tar.xz [RESULTS]
#       on that GPU machine: unpack, run the tests and the benchmark through the bundled loader.
#
# RESULTS defaults to $OUT/gpu-results.txt when OUT is set, else gpu-results.txt in the current
# directory. Exit status: that of restir_gpu_tests (77 = no usable GPU: nothing was checked).
# RESTIR_GPU_DRY_RUN=1 runs the test cases with the CPU standing in for the GPU (a rehearsal on a
# machine without one: every scene loads, every case runs).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
default_results() { if [ -n "${OUT:-}" ]; then echo "$OUT/gpu-results.txt"; else echo "$PWD/gpu-results.txt"; fi; }

# run_checks RESULTS RUNNER...: the tests, then the benchmark, both logged into RESULTS.
run_checks() {
  local results="$1"
  shift
  local bin="$1"
  shift
  local runner=("$@")
  mkdir -p "$(dirname "$results")"
  {
    echo "# restir-lab GPU check, $(date -u +%Y-%m-%dT%H:%MZ), commit ${COMMIT:-$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)}"
    nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null || true
  } >"$results"
  local status=0
  # One process per test case (doctest --first/--last over the file order), each under a time
  # limit: a device error is sticky for the process that hit it, so a fault in one case must not
  # fail the cases after it, and a hang must not eat the machine's minutes.
  echo "== restir_gpu_tests" | tee -a "$results"
  local listing count
  listing="$("${runner[@]}" "$bin/restir_gpu_tests" --no-intro=true --list-test-cases 2>&1)" || status=$?
  if [ "$status" -eq 0 ]; then
    count="$(sed -n 's/.*passing the current filters: \([0-9]*\).*/\1/p' <<<"$listing" | head -1)"
    echo "$listing" | grep -v -e '^\[doctest\]' -e '^====' | tee -a "$results"
    local i case_status failed=0
    for i in $(seq 1 "${count:-0}"); do
      case_status=0
      echo "-- case $i of $count" | tee -a "$results"
      timeout "${GPU_CHECK_CASE_TIMEOUT:-150}" "${runner[@]}" "$bin/restir_gpu_tests" --no-intro=true --first="$i" --last="$i" 2>&1 |
        grep -v 'Film "filename" ignored' | tee -a "$results" || case_status=${PIPESTATUS[0]}
      [ "$case_status" -eq 124 ] && echo "error: case $i ran past ${GPU_CHECK_CASE_TIMEOUT:-150} s" | tee -a "$results"
      [ "$case_status" -ne 0 ] && failed=$((failed + 1))
    done
    echo "restir_gpu_tests: $failed of ${count:-0} cases failed" | tee -a "$results"
    [ "$failed" -ne 0 ] && status=1
  else
    echo "$listing" | tee -a "$results"
  fi
  if [ "$status" -ne 77 ]; then
    echo "== bench_gpu (1920x1080, 1 spp)" | tee -a "$results"
    timeout "${GPU_CHECK_BENCH_TIMEOUT:-240}" "${runner[@]}" "$bin/bench_gpu" --scene "$SCENES_SHARED/scenes/cornell-box/scene-v4.pbrt" \
      --scene "$SCENES_SHARED/scenes/veach-mis/scene-v4.pbrt" --scene "$SCENES_OWN/scenes/teapot.pbrt" \
      --di-scene "$SCENES_OWN/scenes/many-lights.pbrt" --gi-scene "$SCENES_OWN/scenes/teapot.pbrt" \
      --pt-scene "$SCENES_OWN/scenes/teapot.pbrt" 2>&1 |
      grep -v 'Film "filename" ignored' | tee -a "$results" || true
    # Where the GPU frame's time goes: each stage's device time, 1920x1080 (restir render --timings).
    if [ -x "$bin/restir" ]; then
      local integrator scene
      for integrator in restir-di restir-pt pt; do
        case "$integrator" in restir-di) scene="$SCENES_OWN/scenes/many-lights.pbrt" ;; *) scene="$SCENES_OWN/scenes/teapot.pbrt" ;; esac
        echo "== stage times: $integrator, $(basename "$scene"), cuda, 1920x1080, 6 frames" | tee -a "$results"
        timeout 60 "${runner[@]}" "$bin/restir" render "$scene" --integrator "$integrator" --spp 1 --frames 6 --set render.backend=cuda \
          --set film.width=1920 --set film.height=1080 --timings "${TMPDIR:-/tmp}/stages-$integrator.csv" \
          --png "${TMPDIR:-/tmp}/gpu-$integrator.png" -q 2>&1 | grep -v 'Film "filename" ignored' | tee -a "$results" || true
        cat "${TMPDIR:-/tmp}/stages-$integrator.csv" >>"$results" 2>/dev/null || true
      done
      # Replay compaction (pt.replay_compaction, issues 45 and 48): paired reuse's spatial pass with
      # the replaying shifts in a kernel of their own, and without, on the teapots at 1920x1080.
      local compact
      for compact in false true; do
        echo "== stage times: restir-pt, teapot.pbrt, cuda, 1920x1080, 6 frames, paired, pt.replay_compaction=$compact" | tee -a "$results"
        timeout 60 "${runner[@]}" "$bin/restir" render "$SCENES_OWN/scenes/teapot.pbrt" --integrator restir-pt --spp 1 --frames 6 \
          --set render.backend=cuda --set film.width=1920 --set film.height=1080 --set pt.spatial_pairing=paired \
          --set pt.replay_compaction="$compact" --timings "${TMPDIR:-/tmp}/stages-compact-$compact.csv" -o "${TMPDIR:-/tmp}/gpu-compact.exr" \
          -q 2>&1 | grep -v 'Film "filename" ignored' | tee -a "$results" || true
        cat "${TMPDIR:-/tmp}/stages-compact-$compact.csv" >>"$results" 2>/dev/null || true
      done
      # The reuse passes' shadow rays queued and traced in one kernel (render.reuse_rays, issue 48):
      # each stage's device time and rays, to set the CUDA default (docs/gpu.md).
      for integrator in restir-di restir-pt; do
        case "$integrator" in restir-di) scene="$SCENES_OWN/scenes/many-lights.pbrt" ;; *) scene="$SCENES_OWN/scenes/teapot.pbrt" ;; esac
        echo "== stage times: $integrator, $(basename "$scene"), cuda, 1920x1080, 6 frames, render.reuse_rays=queued" | tee -a "$results"
        timeout 60 "${runner[@]}" "$bin/restir" render "$scene" --integrator "$integrator" --spp 1 --frames 6 --set render.backend=cuda \
          --set film.width=1920 --set film.height=1080 --set render.reuse_rays=queued \
          --timings "${TMPDIR:-/tmp}/stages-queued-$integrator.csv" -o "${TMPDIR:-/tmp}/gpu-queued.exr" -q 2>&1 |
          grep -v 'Film "filename" ignored' | tee -a "$results" || true
        cat "${TMPDIR:-/tmp}/stages-queued-$integrator.csv" >>"$results" 2>/dev/null || true
      done
    fi
    [ -x "$bin/restir" ] && [ "${GPU_CHECK_STUDIES:-1}" != 0 ] && run_gpu_studies "$results" "$bin" "${runner[@]}"
  fi
  # "No usable GPU" on a machine whose driver lists one is a failure (a driver or library
  # mismatch, say), not a skip.
  if [ "$status" -eq 77 ] && nvidia-smi -L 2>/dev/null | grep -q GPU; then
    echo "error: nvidia-smi lists a GPU but restir_gpu_tests found none usable (see its first line)" | tee -a "$results"
    status=1
  fi
  echo "results: $results (restir_gpu_tests exit status $status)"
  return "$status"
}

# run_gpu_studies RESULTS BIN RUNNER...: the GPU as the study engine (issue 48). The thesis'
# resolution study (fig. 4.1: pt and ReSTIR PT from 320x180 to 1920x1080) and the equal-time study
# at 1920x1080, each with its references rendered on the GPU too (restir study --set
# render.backend=cuda); their folders (results.csv, plots, report.html) in gpu-studies/ beside
# RESULTS, their CSVs appended to it. Run from the scenes' repository, where the study files'
# relative scene paths resolve in a bundle too. GPU_CHECK_STUDIES=0 skips them;
# GPU_CHECK_STUDY_TIMEOUT (s) limits each.
run_gpu_studies() {
  local results="$1" bin="$2"
  shift 2
  local runner=("$@") study dir
  for study in resolution equal-time; do
    dir="$(dirname "$results")/gpu-studies/$study"
    local sets=(--set render.backend=cuda)
    [ "$study" = equal-time ] && sets+=(--set film.width=1920 --set film.height=1080)
    echo "== study $study on the GPU (${sets[*]}) -> $dir" | tee -a "$results"
    (cd "$SCENES_OWN" && timeout "${GPU_CHECK_STUDY_TIMEOUT:-300}" "${runner[@]}" "$bin/restir" study "$SCENES_OWN/studies/$study.json" \
      --out "$dir" -q "${sets[@]}") 2>&1 | grep -v 'Film "filename" ignored' | tail -20 | tee -a "$results" || true
    [ -f "$dir/results.csv" ] && cat "$dir/results.csv" >>"$results"
  done
}

build_gpu_programs() {  # build_gpu_programs DIR [cmake args...]
  local dir="$1"
  shift
  source "$ROOT/scripts/common.sh"
  install_missing_packages
  cmake -S "$ROOT" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DRESTIR_CUDA=ON -DRESTIR_VIEWER=OFF "$@" >/dev/null
  cmake --build "$dir" -j "$(nproc)" --target restir_gpu_tests bench_gpu restir
}

case "${1:-}" in
  --bundle)
    out="$(realpath -m "${2:?--bundle needs the archive to write}")"
    build_gpu_programs "$ROOT/build-gpu"
    stage="$(mktemp -d)"
    trap 'rm -rf "$stage"' EXIT
    b="$stage/restir-gpu"
    # The repository's layout (repo/scenes beside shared/scenes): scenes refer to ../../shared.
    mkdir -p "$b/bin" "$b/lib" "$b/shared/scenes" "$b/repo/scenes"
    cp "$ROOT/build-gpu/bin/restir_gpu_tests" "$ROOT/build-gpu/bin/bench_gpu" "$ROOT/build-gpu/bin/restir" "$b/bin/"
    # Every library the programs load, resolved through links; the CUDA driver (libcuda) is the GPU
    # machine's own and is not linked here (the static CUDA runtime opens it at run time).
    for lib in $(ldd "$b/bin/restir_gpu_tests" "$b/bin/bench_gpu" "$b/bin/restir" | awk '$2 == "=>" && $3 ~ /^\// {print $3} $1 ~ /^\/.*ld-linux/ {print $1}' | sort -u); do
      cp -L "$lib" "$b/lib/$(basename "$lib")"
    done
    # The rest of this glibc: the programs do not link them, but the CUDA driver (libcuda, opened
    # at run time by the static CUDA runtime) does, and the GPU machine's own copies would not
    # match the bundled libc.
    libc_dir="$(dirname "$(ldd "$b/bin/restir_gpu_tests" | awk '$1 == "libc.so.6" {print $3}')")"
    for lib in libdl.so.2 libpthread.so.0 librt.so.1; do
      [ -e "$libc_dir/$lib" ] && cp -L "$libc_dir/$lib" "$b/lib/$lib"
    done
    cp -r "$ROOT/../shared/scenes/cornell-box" "$ROOT/../shared/scenes/veach-mis" "$ROOT/../shared/scenes/envmaps" "$b/shared/scenes/"
    cp -r "$ROOT/scenes/." "$b/repo/scenes/"
    cp -r "$ROOT/studies" "$b/repo/"  # run_gpu_studies
    git -C "$ROOT" describe --always --dirty >"$b/COMMIT" 2>/dev/null || echo unknown >"$b/COMMIT"
    tar -C "$stage" -cJf "$out.tmp" restir-gpu
    mv "$out.tmp" "$out"
    echo "bundle: $out ($(du -h "$out" | cut -f1))"
    ;;
  --from-bundle)
    archive="$(realpath "${2:?--from-bundle needs the archive}")"
    results="$(realpath -m "${3:-$(default_results)}")"
    dest="$(mktemp -d)"
    tar -C "$dest" -xJf "$archive"
    b="$dest/restir-gpu"
    export RESTIR_SHARED_DIR="$b/shared" RESTIR_SOURCE_DIR="$b/repo" RESTIR_BINARY_DIR="$dest"
    COMMIT="$(cat "$b/COMMIT")"
    SCENES_SHARED="$b/shared" SCENES_OWN="$b/repo"
    loader="$(ls "$b"/lib/ld-linux-*.so.* | head -1)"
    run_checks "$results" "$b/bin" "$loader" --library-path "$b/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
    ;;
  -*)
    echo "unknown argument: $1" >&2
    exit 2
    ;;
  *)
    results="$(realpath -m "${1:-$(default_results)}")"
    build_gpu_programs "$ROOT/build-gpu" -DCMAKE_CUDA_ARCHITECTURES=native
    SCENES_SHARED="$ROOT/../shared" SCENES_OWN="$ROOT"
    run_checks "$results" "$ROOT/build-gpu/bin" env
    ;;
esac
