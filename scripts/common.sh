# Shared by the setup scripts: install missing Debian packages, configure and build.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PACKAGES=(g++ cmake ninja-build pkg-config libembree-dev libtbb-dev libopenexr-dev libstb-dev
  libtinyobjloader-dev libtinygltf-dev libcli11-dev nlohmann-json3-dev libfmt-dev doctest-dev gnuplot-nox
  libglfw3-dev libimgui-dev libgl-dev  # these three: the viewer, `restir view` (CMake option RESTIR_VIEWER)
  python3-venv python3-dev)  # the Python module restirlab (RESTIR_PYTHON; its PyPI packages: python_venv)

install_missing_packages() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "installing Debian packages: ${missing[*]}"
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
}

# install_optional_packages PKG...: what only some tests need (Slurm for the cluster test). A
# machine without a package source keeps going: those tests report themselves skipped.
install_optional_packages() {
  local missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -gt 0 ] || return 0
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo -n"
  echo "installing optional Debian packages: ${missing[*]}"
  if ! { $sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"; }; then
    echo "warning: could not install ${missing[*]}: the tests that need them will be skipped" >&2
  fi
}

# configure DIR [extra cmake args...]
configure() {
  local dir="$1"
  shift
  cmake -S "$ROOT" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
}

# build DIR [extra cmake args...]: configure and build every target (tests, benchmarks, and the CUDA
# backend where nvcc is installed). -URESTIR_CUDA forgets a choice the main job cached, so the test
# command builds the CUDA backend wherever CMake finds nvcc, GPU or not.
build() {
  local dir="$1"
  shift
  configure "$dir" -URESTIR_CUDA "$@"
  cmake --build "$dir" -j "$(nproc)"
}

# gpu_present: an NVIDIA GPU this machine can run on (nvidia-smi lists one).
gpu_present() {
  command -v nvidia-smi >/dev/null 2>&1 && nvidia-smi -L 2>/dev/null | grep -q '^GPU '
}

# python_venv DIR: a virtual environment with what the Python module's build and tests need from
# PyPI (tests/python/requirements.txt; nanobind has no Debian package); prints its interpreter.
python_venv() {
  local dir="$1"
  [ -x "$dir/bin/python" ] || python3 -m venv "$dir" >&2
  "$dir/bin/python" -m pip install -q --disable-pip-version-check -r "$ROOT/tests/python/requirements.txt" >&2
  echo "$dir/bin/python"
}
