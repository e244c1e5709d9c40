#!/usr/bin/env bash
# Run the dynamic D-series scenes (D1, D2, D3) with all four integrators and draw their energy
# and momentum (docs/d1_energy.png, docs/d2_energy.png, docs/d3_energy.png). About 2 minutes.
#   scripts/d_series.sh [OUT_DIR]   (default out/d_series)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-out/d_series}"
for scene in flying_spaghetti_2d:d1 flying_spaghetti_3d:d2 right_angle_cantilever:d3; do
  name="${scene%%:*}"; tag="${scene##*:}"; dirs=()
  for integrator in energy-momentum midpoint newmark hht; do
    dir="$out/$name-$integrator"
    # Newmark and HHT are expected to fail on some of these (exit code 1): keep going.
    "$here/scripts/slidebeam" run "$here/runs/$name.toml" --out "$dir" -q \
      --set "analysis.integrator=\"$integrator\"" || true
    dirs+=("$dir")
  done
  "$here/scripts/slidebeam" plot "${dirs[@]}" --out "$here/docs/${tag}_energy.png"
done
