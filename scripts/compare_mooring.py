#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The mooring chain of runs/cables/mooring_line.toml at rest: slidebeam's equilibrium start against
the quasi-static catenary on a frictionless seabed, as slidebeam.scene.catenary.MooringLine computes it
and, when installed, as MoorPy does (its Catenary function: the line model of MoorPy and of
MoorDyn's static solve). Prints one table: fairlead tension, the anchor's horizontal pull, the
length of chain on the seabed, and the errors against MoorPy.

MoorPy is not a dependency of the project. To compare with it, use a throwaway venv that sees
Debian's packages:

    /usr/bin/python3 -m venv --system-site-packages /tmp/peers && /tmp/peers/bin/pip install moorpy
    /tmp/peers/bin/python scripts/compare_mooring.py [--spans 110 220]
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "python"))

import numpy as np  # noqa: E402

SPAN, DEPTH, LENGTH, EA, W = 200.0, 50.0, 220.0, 5e8, 1000.0  # the scene's line, submerged weight W N/m


def slidebeam_line(spans: int) -> tuple[float, float, float]:
    """(fairlead tension, anchor's horizontal pull, chain on the seabed in unstretched m) after the
    scene's equilibrium start."""
    import petsc4py

    petsc4py.init([])
    import slidebeam

    scene = slidebeam.load_scene(ROOT / "runs" / "cables" / "mooring_line.toml",
                                 [f"beam.chain.spans={spans}", "analysis.t_end=1e-9", "output.xdmf=false"])
    sim = slidebeam.Simulation(scene)
    sim.settle()
    f = {r.effect: np.asarray(r.force) for r in sim.reactions()}
    samples = sim.sample_beam("chain", samples_per_span=8)
    on_bed = samples["s"][samples["position"][:, 2] < -DEPTH + 2e-3]  # within 2 mm of the bed (it sinks 0.1 mm)
    return float(np.linalg.norm(f["spherical[chain@end]"])), float(-f["spherical[chain@start]"][0]), float(on_bed.max())


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--spans", type=int, nargs="+", default=[110, 220], help="meshes of the chain (default 110 220)")
    args = p.parse_args()
    from slidebeam.scene.catenary import MooringLine

    exact = MooringLine(span=SPAN, height=DEPTH, length=LENGTH, EA=EA, w=W)
    rows = [("slidebeam.scene.catenary.MooringLine", exact.fairlead_tension, exact.H, LENGTH - exact.suspended_length)]
    try:
        from moorpy.Catenary import catenary  # type: ignore[import-not-found]

        fAH, _, fBH, fBV, info = catenary(SPAN, DEPTH, LENGTH, EA, W, CB=0.0, Tol=1e-10)
        moorpy = (math.hypot(fBH, fBV), fAH, float(info["LBot"]))
        rows.append(("MoorPy (Catenary, CB = 0)", *moorpy))
    except ImportError:
        moorpy = None
        print("MoorPy is not installed here: see this script's docstring to compare with it", file=sys.stderr)
    for spans in args.spans:
        rows.append((f"slidebeam, {spans} spans", *slidebeam_line(spans)))
    ref = moorpy or rows[0][1:]
    print("| line | fairlead tension, N | error | anchor's horizontal pull, N | error | chain on the seabed, m |")
    print("|---|---|---|---|---|---|")
    for name, T, H, bed in rows:
        print(f"| {name} | {T:.2f} | {abs(T / ref[0] - 1):.1e} | {H:.2f} | {abs(H / ref[1] - 1):.1e} | {bed:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
