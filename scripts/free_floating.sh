#!/usr/bin/env bash
# Run the free-floating scenes of issue 21 (runs/free_floating/) with the frame-projected sliding
# joint (the default) and the spatial one, under energy-momentum and the midpoint rule, and draw
# their energy and momentum drift (docs/free_floating_two_beams.png,
# docs/free_floating_three_beams.png). About 20 seconds.
#   scripts/free_floating.sh [OUT_DIR]   (default out/free_floating)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-out/free_floating}"
for scene in two_beams:1 three_beams:2; do
  name="${scene%%:*}"; joints="${scene##*:}"; spatial=()
  for ((k = 0; k < joints; k++)); do spatial+=(--set "sliding_joint.$k.form=\"spatial\""); done
  dirs=()
  for integrator in energy-momentum midpoint; do
    tag="${integrator/energy-momentum/em}"
    "$here/scripts/slidebeam" run "$here/runs/free_floating/$name.toml" --out "$out/$name-frame-$tag" -q \
      --set "analysis.integrator=\"$integrator\""
    "$here/scripts/slidebeam" run "$here/runs/free_floating/$name.toml" --out "$out/$name-spatial-$tag" -q \
      --set "analysis.integrator=\"$integrator\"" "${spatial[@]}"
    dirs+=("$out/$name-frame-$tag" "$out/$name-spatial-$tag")
  done
  "$here/scripts/slidebeam" plot "${dirs[@]}" --drift --out "$here/docs/free_floating_$name.png"
done
