#!/usr/bin/env bash
# Fuzzes the scene loaders (pbrt tokenizer/parser, PLY, OBJ, glTF) with libFuzzer, SECONDS per
# target (default 60): `scripts/fuzz.sh 1800` runs 30 minutes per target.
# Needs clang with libFuzzer (Debian 12: the `clang` package ships libclang_rt.fuzzer); builds
# build-fuzz/ with ASan + UBSan. New inputs go to build-fuzz/corpus/<target> (seeded from the
# committed fuzz/corpus/<target>); crashes to build-fuzz/crashes/<target>/. Exits 1 if any target
# found a crash, a leak, a timeout (> 10 s per input) or ran out of memory.
set -euo pipefail
SECONDS_PER_TARGET="${1:-60}"
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
BUILD="$ROOT/build-fuzz"
JOBS="${FUZZ_BUILD_JOBS:-2}"
if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: clang++ not found; install it with: apt-get install -y clang" >&2
  exit 1
fi
cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
  -DCMAKE_CXX_COMPILER=clang++ -DRESTIR_BUILD_FUZZ=ON -DRESTIR_BUILD_TESTS=OFF -DRESTIR_BUILD_BENCH=OFF >/dev/null
cmake --build "$BUILD" -j"$JOBS" --target fuzz_pbrt fuzz_ply fuzz_obj fuzz_gltf
status=0
for t in pbrt ply obj gltf; do
  mkdir -p "$BUILD/corpus/$t" "$BUILD/crashes/$t"
  echo "== fuzz_$t for ${SECONDS_PER_TARGET} s"
  if ! ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
      "$BUILD/bin/fuzz_$t" "$BUILD/corpus/$t" "$ROOT/fuzz/corpus/$t" -max_total_time="$SECONDS_PER_TARGET" \
      -timeout=10 -close_fd_mask=2 -rss_limit_mb=4096 -max_len=65536 -artifact_prefix="$BUILD/crashes/$t/" -print_final_stats=1 \
      > "$BUILD/fuzz_$t.log" 2>&1; then
    echo "fuzz_$t: FAILED (see $BUILD/fuzz_$t.log and $BUILD/crashes/$t/)"
    tail -30 "$BUILD/fuzz_$t.log"
    status=1
  else
    grep -E "^stat::number_of_executed_units|^#[0-9]+.*DONE" "$BUILD/fuzz_$t.log" | tail -2 || true
    echo "fuzz_$t: clean"
  fi
done
exit $status
