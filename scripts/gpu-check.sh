#!/usr/bin/env bash
# Issue 16's one prepared command for a machine with an NVIDIA GPU: builds the CUDA backend, runs
# restir_gpu_tests (CPU and CUDA backends agree) and bench_gpu (1920x1080), and writes a results
# file. Meant to finish in under 6 minutes on one H200.
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
  {
    echo "# restir-lab GPU check, $(date -u +%Y-%m-%dT%H:%MZ), commit ${COMMIT:-$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)}"
    nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null || true
  } >"$results"
  local status=0
  echo "== restir_gpu_tests" | tee -a "$results"
  "${runner[@]}" "$bin/restir_gpu_tests" --no-intro=true 2>&1 | grep -v 'Film "filename" ignored' | tee -a "$results" || status=${PIPESTATUS[0]}
  if [ "$status" -ne 77 ]; then
    echo "== bench_gpu (1920x1080, 1 spp)" | tee -a "$results"
    "${runner[@]}" "$bin/bench_gpu" --scene "$SCENES_SHARED/scenes/cornell-box/scene-v4.pbrt" \
      --scene "$SCENES_SHARED/scenes/veach-mis/scene-v4.pbrt" --scene "$SCENES_OWN/scenes/teapot.pbrt" \
      --di-scene "$SCENES_OWN/scenes/many-lights.pbrt" --gi-scene "$SCENES_OWN/scenes/teapot.pbrt" \
      --pt-scene "$SCENES_OWN/scenes/teapot.pbrt" 2>&1 |
      grep -v 'Film "filename" ignored' | tee -a "$results" || true
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

build_gpu_programs() {  # build_gpu_programs DIR [cmake args...]
  local dir="$1"
  shift
  source "$ROOT/scripts/common.sh"
  install_missing_packages
  cmake -S "$ROOT" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DRESTIR_CUDA=ON -DRESTIR_VIEWER=OFF "$@" >/dev/null
  cmake --build "$dir" -j "$(nproc)" --target restir_gpu_tests bench_gpu
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
    cp "$ROOT/build-gpu/bin/restir_gpu_tests" "$ROOT/build-gpu/bin/bench_gpu" "$b/bin/"
    # Every library the programs load, resolved through links; the CUDA driver (libcuda) is the GPU
    # machine's own and is not linked here (the static CUDA runtime opens it at run time).
    for lib in $(ldd "$b/bin/restir_gpu_tests" "$b/bin/bench_gpu" | awk '$2 == "=>" && $3 ~ /^\// {print $3} $1 ~ /^\/.*ld-linux/ {print $1}' | sort -u); do
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
    git -C "$ROOT" rev-parse --short HEAD >"$b/COMMIT" 2>/dev/null || echo unknown >"$b/COMMIT"
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
