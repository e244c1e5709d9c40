#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The zip line, director rope against ANCF cable: prints the table of docs/verification.md,
"The zip line: director rope against ANCF cable".

runs/cables/zip_line.toml (a 20 m steel rope, an 80 kg trolley held on it) settled by its
equilibrium start, the rope an assumed-strain director beam or an ANCF cable of the same EA, EI
and rhoA, at 40 / 80 / 160 spans. "Converged" is the director rope at 320 spans. Per mesh:

  - the trolley's place: director - ANCF, director - converged, ANCF - converged (m)
  - the tension 1 m and more from the trolley, largest difference as a fraction of the support
    tension: the same three, and full quadrature - converged

    scripts/zip_line_table.py            # about a minute
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))
sys.path.insert(0, str(ROOT / "tests" / "python"))

SPANS = (40, 80, 160)
CONVERGED_SPANS = 320
AWAY = 1.0  # m from the trolley: the tension jumps there by the slider's tangential reaction


def main() -> int:
    argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    import numpy as np

    from test_catenary import _zip_line

    def settled(formulation: str, spans: int, sets: list[str] | None = None):
        sim = _zip_line(formulation, spans, sets)
        sim.settle()
        field = sim.sample_beam("rope", samples_per_span=8)
        return np.array(sim.tracked_points()[0]), field["s"], field["tension"], sim.joint_states()[0].s

    ref_place, ref_s, ref_T, ref_trolley = settled("director", CONVERGED_SPANS)
    support = float(max(ref_T[0], ref_T[-1]))

    def tension_gap(a, b) -> float:
        """Largest difference of two settled ropes' tensions 1 m and more from the trolley, on a's
        samples, over the support tension."""
        _, s, T, trolley = a
        other = np.interp(s, b[1], b[2])
        away = np.abs(s - trolley) >= AWAY
        return float(np.abs(T - other)[away].max()) / support

    ref = (ref_place, ref_s, ref_T, ref_trolley)
    print(f"Support tension (director rope, {CONVERGED_SPANS} spans): {support / 1e3:.2f} kN\n")
    print("| spans | trolley place: director − ANCF / director − converged / ANCF − converged | tension: director − "
          "ANCF / director − converged / ANCF − converged / full quadrature − converged |")
    print("|---|---|---|")
    for n in SPANS:
        d, a = settled("director", n), settled("ancf", n)
        full = settled("director", n, ["beam.0.quadrature=full"])
        places = [np.linalg.norm(d[0] - a[0]), np.linalg.norm(d[0] - ref_place), np.linalg.norm(a[0] - ref_place)]
        tensions = [tension_gap(d, a), tension_gap(d, ref), tension_gap(a, ref), tension_gap(full, ref)]
        print(f"| {n} | " + " / ".join(f"{x:.1e}" for x in places) + " m | " +
              " / ".join(f"{x:.1e}" for x in tensions) + " |", flush=True)
    ancf_ref = settled("ancf", CONVERGED_SPANS)
    print(f"\nANCF cable at {CONVERGED_SPANS} spans against the director rope: trolley "
          f"{np.linalg.norm(ancf_ref[0] - ref_place):.1e} m, tension {tension_gap(ancf_ref, ref) * support:.2f} N")
    return 0


if __name__ == "__main__":
    sys.exit(main())
