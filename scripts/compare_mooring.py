#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The mooring chain of runs/cables/mooring_line.toml at rest: slidebeam's equilibrium start against
the quasi-static catenary on a frictionless seabed, as slidebeam.scene.catenary.MooringLine computes it
and, when installed, as MoorPy does (its Catenary function: the line model of MoorPy and of
MoorDyn's static solve). Prints one table: fairlead tension, the anchor's horizontal pull, the
length of chain on the seabed, and the errors against MoorPy. With --friction, the same chain on a
seabed with friction, pulled out and left at rest, against the closed form with seabed friction.

MoorPy is not a dependency of the project. To compare with it, use a throwaway venv that sees
Debian's packages:

    /usr/bin/python3 -m venv --system-site-packages /tmp/peers && /tmp/peers/bin/pip install moorpy
    /tmp/peers/bin/python scripts/compare_mooring.py [--spans 110 220] [--friction 0 0.1 0.5 1.5]
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


START_SPAN, PULL, RAMP, SETTLE = 175.0, 30.0, 30.0, 30.0  # the friction runs: from 175 m out to 205 m


def pulled_scene(mu: float, spans: int, ramp: float = RAMP, settle: float = SETTLE, dt: float | None = None):
    """The scene's chain on a seabed with friction mu: from the frictionless equilibrium start with
    the fairlead at START_SPAN (1.6 kN of horizontal tension), pulled out by PULL over `ramp`
    seconds and left to settle for `settle` more (the bed damped, the chain's swing damped by
    mass-proportional damping, which vanishes at rest). A line pulled out mobilises the seabed's
    friction against the pull along its grounded part, as MoorPy's model of seabed friction
    assumes, wherever its tension grew."""
    import slidebeam
    from slidebeam.scene.catenary import MooringLine

    scene = slidebeam.load_scene(ROOT / "runs" / "cables" / "mooring_line.toml",
                                 [f"beam.chain.spans={spans}", f"analysis.t_end={ramp + settle}", "output.xdmf=false",
                                  "output.every=20", *([f"analysis.dt={dt}"] if dt else [])])
    data = dict(scene.data)
    # drawn along the frictionless catenary at START_SPAN (the start then has little to do)
    start = MooringLine(span=START_SPAN, height=DEPTH, length=LENGTH, EA=EA, w=W)
    H, hanging = start.H, start.suspended_length
    points = [[0.0, 0.0, -DEPTH], [start.touchdown, 0.0, -DEPTH]]
    for u in np.linspace(0.0, hanging, 25)[1:]:
        a = W * u / H
        points.append([start.touchdown + H / W * math.asinh(a) + H * u / EA, 0.0,
                       -DEPTH + H / W * (math.sqrt(1.0 + a * a) - 1.0) + W * u * u / (2.0 * EA)])
    points[-1] = [START_SPAN, 0.0, 0.0]
    data["beam"] = [{**data["beam"][0], "polyline": points}]
    fairlead = data["support"][1]
    data["support"] = [data["support"][0], {**fairlead, "motion": {
        "displacement": [PULL, 0.0, 0.0], "time_function": {"type": "smooth_ramp", "t0": 0.0, "t1": ramp}}}]
    k = data["contact"][0]["stiffness"]
    rhoA = data["beam"][0]["section"]["rhoA"]
    data["contact"] = [{**data["contact"][0], "mu": mu, "damping": 2 * 0.3 * math.sqrt(k * rhoA)}]
    data["damping"] = [{**data["damping"][0], "mass_proportional": 1.0}]
    return slidebeam.scene_from_dict(data)


def line_at_rest(sim, record) -> tuple[float, float, float]:
    """(fairlead tension, anchor's horizontal pull, chain on the seabed in unstretched m: where it
    lies within 2 mm of the bed) of a record of the scene's chain."""
    f = {r.effect: np.asarray(r.force) for r in record.reactions}
    samples = sim.sample_beam("chain", samples_per_span=8)
    on_bed = samples["s"][samples["position"][:, 2] < -DEPTH + 2e-3]  # (it sinks 0.1 mm)
    return float(np.linalg.norm(f["spherical[chain@end]"])), float(-f["spherical[chain@start]"][0]), float(on_bed.max())


def pulled_line(mu: float, spans: int) -> tuple[float, float, float, float]:
    """line_at_rest of pulled_scene at its end, and the run's wall time."""
    import time

    import petsc4py

    petsc4py.init([])
    import slidebeam

    started = time.perf_counter()
    sim = slidebeam.Simulation(pulled_scene(mu, spans))
    record = sim.run_dynamic().records[-1]
    return (*line_at_rest(sim, record), time.perf_counter() - started)


def friction_table(spans: list[int], coefficients: list[float]) -> None:
    """The pulled-out line against the closed form with seabed friction (MooringLine, friction) and
    MoorPy's Catenary with CB = mu."""
    from slidebeam.scene.catenary import MooringLine

    span = START_SPAN + PULL
    try:
        from moorpy.Catenary import catenary  # type: ignore[import-not-found]
    except ImportError:
        catenary = None
        print("MoorPy is not installed here: see this script's docstring to compare with it", file=sys.stderr)
    print("| seabed friction | line | fairlead tension, N | error | anchor's horizontal pull, N | error (of H) | "
          "chain on the seabed, m | wall, s |")
    print("|---|---|---|---|---|---|---|---|")
    for mu in coefficients:
        exact = MooringLine(span=span, height=DEPTH, length=LENGTH, EA=EA, w=W, friction=mu)
        ref = (exact.fairlead_tension, exact.anchor_tension, LENGTH - exact.suspended_length)
        print(f"| {mu} | MooringLine | {ref[0]:.2f} | | {ref[1]:.2f} | | {ref[2]:.2f} | |")
        if catenary is not None:
            fAH, _, fBH, fBV, info = catenary(span, DEPTH, LENGTH, EA, W, CB=mu, Tol=1e-10)
            print(f"| {mu} | MoorPy (Catenary, CB = {mu}) | {math.hypot(fBH, fBV):.2f} | | {fAH:.2f} | | "
                  f"{float(info['LBot']):.2f} | |")
        for n in spans:
            T, H, bed, wall = pulled_line(mu, n)
            print(f"| {mu} | slidebeam, {n} spans | {T:.2f} | {T / ref[0] - 1:+.1e} | {H:.2f} | "
                  f"{(H - ref[1]) / exact.H:+.1e} | {bed:.2f} | {wall:.1f} |", flush=True)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--spans", type=int, nargs="+", default=[110, 220], help="meshes of the chain (default 110 220)")
    p.add_argument("--friction", type=float, nargs="*",
                   help="seabed friction coefficients: the line pulled out from 175 m to 205 m, then at rest, "
                        "against the closed form with friction (e.g. --friction 0 0.1 0.5 1.5)")
    args = p.parse_args()
    if args.friction:
        friction_table(args.spans, args.friction)
        return 0
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
