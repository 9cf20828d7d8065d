#!/usr/bin/env bash
# Validates restir-lab's reference path tracer against Mitsuba 3 (a second, independent reference).
# Every scene in scenes/*.pbrt and the shared scenes (furnace, cornell-box, veach-mis) is exported with
# `restir export-mitsuba`, rendered by both at a small resolution and equal max depth, and compared
# (image mean within 1 %, 8x8 block means within 3 %, both against the renderers' standard errors).
# Prints a Markdown table; exit status 1 if a scene differs beyond noise.
#   scripts/validate-mitsuba.sh [--shared DIR] [--no-build] [-- extra args for validate_mitsuba.py]
#   e.g. ... -- --width 96 --spp 256 --mitsuba-spp 256     (quicker)
# Installs Mitsuba 3 (and numpy) with pip if they are missing; nothing else depends on them.
source "$(dirname "$0")/common.sh"
SHARED="$ROOT/../shared"
do_build=1
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --shared) SHARED="$2"; shift 2 ;;
    --no-build) do_build=0; shift ;;
    --) shift; extra=("$@"); break ;;
    *) echo "error: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
[ -d "$SHARED/scenes" ] || { echo "error: no shared scenes in '$SHARED' (give --shared DIR)" >&2; exit 2; }

if [ "$do_build" = 1 ]; then
  install_missing_packages
  build "$ROOT/build" -DRESTIR_BUILD_TESTS=OFF
fi
if ! python3 -c "import mitsuba, numpy" 2>/dev/null; then
  echo "installing mitsuba and numpy with pip" >&2
  python3 -m pip install --quiet mitsuba numpy
fi

cd "$ROOT"
scenes=(scenes/*.pbrt)
# The furnace also at depth 1: its exact value there (1.5) pins the max-depth mapping.
scenes+=("$SHARED/scenes/furnace.pbrt@1" "$SHARED/scenes/furnace.pbrt")
for s in "$SHARED"/scenes/*/scene-v4.pbrt; do scenes+=("$s"); done
# Tiny analytic cases (expected values in their headers and the README).
scenes+=(scripts/mitsuba-cases/*.pbrt)
exec python3 "$ROOT/scripts/validate_mitsuba.py" --restir "$ROOT/build/bin/restir" \
  --out "$ROOT/out/mitsuba-validation" "${extra[@]}" "${scenes[@]}"
