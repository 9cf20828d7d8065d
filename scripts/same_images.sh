#!/usr/bin/env bash
# Two builds of restir, the same renders, compared pixel for pixel (restir compare's MAE): what a
# refactor that should change no image must show (issue 43: one frame per algorithm, against the
# binary before it). Each integrator on three scenes; restir-pt with every shift x spatial MIS;
# animated scenes; debug views; two chains. Prints one line per case (MAE, integrator, scene,
# options); exits 1 if any image differs or either build fails a render.
#   scripts/same_images.sh OLD_RESTIR NEW_RESTIR [RES]      (RES default 96x64)
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
old="$1"; new="$2"; res="${3:-96x64}"
S="$root/../shared/scenes"; O="$root/scenes"
three=("$S/cornell-box/scene-v4.pbrt" "$O/teapot.pbrt" "$O/env-object.pbrt")
cases=()
for s in "${three[@]}"; do
  cases+=("pt|$s|--spp 4 --set path.max_depth=5")
  cases+=("restir-di|$s|--spp 2 --frames 3")
  cases+=("restir-gi|$s|--spp 1 --frames 3 --set path.max_depth=4")
  for shift in hybrid reconnection random-replay; do
    for mis in pairwise generalized-balance one-over-z; do
      cases+=("restir-pt|$s|--spp 1 --frames 3 --set path.max_depth=4 --set pt.shift=$shift --set pt.spatial_mis=$mis")
    done
  done
  cases+=("ssr|$s|--spp 1 --frames 2")
done
cases+=(
  "restir-di|$O/many-lights.pbrt|--spp 1 --frames 3 --set di.temporal_mis=pairwise"
  "restir-di|$O/env-object.pbrt|--spp 1 --frames 3 --set di.bsdf_candidates=2 --set di.visibility_reuse=false"
  "restir-di|$O/dynamic-room.pbrt|--spp 1 --frames 4"
  "restir-di|$O/dynamic-room.pbrt|--spp 1 --frames 4 --set di.history_scene=current"
  "restir-gi|$O/dynamic-room.pbrt|--spp 1 --frames 4 --set path.max_depth=3"
  "restir-pt|$O/dynamic-room.pbrt|--spp 1 --frames 4 --set pt.shift=random-replay"
  "restir-pt|$O/moving-glossy.pbrt|--spp 1 --frames 4 --set pt.history_scene=current"
  "restir-pt|$O/mirror-glass.pbrt|--spp 2 --frames 3 --set pt.direct=restir-di --set path.max_depth=3"
  "restir-pt|$O/teapot.pbrt|--spp 1 --frames 2 --set render.debug_view=reconnection-depth"
  "restir-di|$O/many-lights.pbrt|--spp 1 --frames 2 --set render.debug_view=reuse-source"
  "pt|$O/dynamic-room.pbrt|--spp 2 --frames 3"
  "ssr|$O/mirror-floor.pbrt|--spp 2 --frames 2 --set ssr.temporal=true"
)
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail=0
for c in "${cases[@]}"; do
  IFS='|' read -r integrator scene args <<< "$c"
  # shellcheck disable=SC2086
  if ! "$old" render "$scene" --integrator "$integrator" --res "$res" -q -o "$tmp/a.exr" $args 2>/dev/null; then echo "old build failed: $c"; fail=1; continue; fi
  # shellcheck disable=SC2086
  if ! "$new" render "$scene" --integrator "$integrator" --res "$res" -q -o "$tmp/b.exr" $args 2>/dev/null; then echo "new build failed: $c"; fail=1; continue; fi
  mae=$("$new" compare "$tmp/b.exr" "$tmp/a.exr" --json | sed -n 's/.*"mae": *\([^,}]*\).*/\1/p')
  echo "$mae  $integrator $(basename "$(dirname "$scene")")/$(basename "$scene") $args"
  [ "$mae" = "0" ] || [ "$mae" = "0.0" ] || fail=1
done
echo "${#cases[@]} cases: $([ $fail = 0 ] && echo 'every image the same' || echo 'DIFFERENCES')"
exit $fail
