#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite (unit + statistical tests).
#   scripts/test.sh             Release build in build/
#   scripts/test.sh --sanitize  ASan + UBSan build in build-asan/
#   scripts/test.sh --fast      skip the tests labelled "slow"
source "$(dirname "$0")/common.sh"
dir="$ROOT/build"
cmake_args=()
ctest_args=()
for a in "$@"; do
  case "$a" in
    --sanitize) dir="$ROOT/build-asan"; cmake_args+=(-DRESTIR_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo) ;;
    --fast) ctest_args+=(-LE slow) ;;
    *) echo "unknown argument: $a" >&2; exit 2 ;;
  esac
done
install_missing_packages
install_optional_packages slurm-wlm munge  # tests/study/slurm_study.sh: a private one-node Slurm cluster
install_optional_packages xvfb xauth libgl1-mesa-dri libglx-mesa0 xdotool  # tests/viewer/viewer_script.sh: the viewer under Xvfb + Mesa
# The Python module and its tests (ctest's `python`); not under the sanitizers, which a Python
# interpreter does not load.
[ "$dir" = "$ROOT/build-asan" ] || cmake_args+=(-DRESTIR_PYTHON=ON -DPython_EXECUTABLE="$(python_venv "$dir/pyenv")")
build "$dir" "${cmake_args[@]}"
cd "$dir"
ctest -j "$(nproc)" --output-on-failure --timeout 900 "${ctest_args[@]}"
