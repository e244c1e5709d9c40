#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The mooring chain of runs/cables/mooring_line.toml at rest: slidebeam's equilibrium start against
the quasi-static catenary on a frictionless seabed, as slidebeam.scene.catenary.MooringLine computes it
and, when installed, as MoorPy does (its Catenary function: the line model of MoorPy and of
MoorDyn's static solve). Prints one table: fairlead tension, the anchor's horizontal pull, the
length of chain on the seabed, and the errors against MoorPy. With --friction, the same chain on a
seabed with friction, pulled out and left at rest, against the closed form with seabed friction.
--chains: MoorDyn's quasi-static chain cases; --moving: the line moved by its fairlead beside
MoorDyn; --jumper, --jumper-moving: Lowe & Langley's jumper at rest and under its top's motions
(beside MoorDyn; --figure draws the three cases).

MoorPy and MoorDyn are not dependencies of the project. To compare with them, use a throwaway
venv that sees Debian's packages:

    /usr/bin/python3 -m venv --system-site-packages /tmp/peers && /tmp/peers/bin/pip install moorpy moordyn
    /tmp/peers/bin/python scripts/compare_mooring.py [--spans 110 220] [--friction 0 0.1 0.5 1.5]
    /tmp/peers/bin/python scripts/compare_mooring.py --jumper-moving --spans 68 136 --dt 0.05 0.0125
"""
from __future__ import annotations

import argparse
import contextlib
import math
import os
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


# The quasi-static chain cases MoorDyn validates against (its tests/quasi_static_chain.cpp and
# tests/Mooring/WD*_Chain.txt, https://github.com/FloatingArrayDesign/MoorDyn): a chain of 390 kg/m,
# EA = 1.674e9 N, 0.252 m volume-equivalent diameter, in sea water (1025 kg/m^3, g = 9.80665), from
# an anchor on the seabed to a fairlead at the surface, at three depths. depth: (anchor to fairlead,
# unstretched length, MoorDyn's segments, fairlead and anchor tension predicted by quasi-static codes, kN)
CHAIN_CASES = {
    50.0: (400.0, 410.0, 41, 991.6, 826.2),
    200.0: (700.0, 760.0, 76, 2065.4, 1402.2),
    600.0: (1500.0, 1700.0, 170, 5232.6, 3244.2),
}
CHAIN_RHO_A, CHAIN_EA, CHAIN_D, SEA, G = 390.0, 1.674e9, 0.252, 1025.0, 9.80665
CHAIN_W = (CHAIN_RHO_A - SEA * math.pi / 4 * CHAIN_D**2) * G  # submerged weight, N/m


def chain_scene_data(depth: float, spans: int) -> dict:
    """One of CHAIN_CASES as a scene (a dict for slidebeam.scene_from_dict): drawn along the seabed
    and then straight up to the fairlead, a polyline as long as the chain; the equilibrium start
    lays it on a stiff frictionless bed (it sinks 0.3 mm) and hangs the rest."""
    span, length = CHAIN_CASES[depth][:2]
    corner = (span**2 + depth**2 - length**2) / (2.0 * (span - length))  # where the drawing leaves the bed
    return {
        "scene": {"name": f"chain_wd{int(depth):04d}"},
        "analysis": {"type": "dynamic", "start": "equilibrium", "dt": 0.1, "t_end": 1e-9},
        "beam": [{"name": "chain", "polyline": [[0.0, 0.0, -depth], [corner, 0.0, -depth], [span, 0.0, 0.0]],
                  "unstretched_length": length, "spans": spans,
                  "section": {"EA": CHAIN_EA, "kGA": 0.9 * CHAIN_EA / 2.6, "GJ": 1e3, "EI2": 1e4, "EI3": 1e4,
                              "rhoA": CHAIN_RHO_A, "rhoI2": 1e-2, "rhoI3": 1e-2}}],
        "support": [{"type": "spherical", "beam": "chain", "at": "start"},
                    {"type": "spherical", "beam": "chain", "at": "end"}],
        "gravity": {"g": [0.0, 0.0, -G]},
        "contact": [{"type": "plane", "beam": "chain", "point": [0.0, 0.0, -depth], "normal": [0.0, 0.0, 1.0],
                     "stiffness": 1e7}],
        "buoyancy": [{"beam": "chain", "density": SEA, "diameter": CHAIN_D, "surface": [0.0, 0.0, 0.0]}],
        "output": {"xdmf": False},
    }


def chain_at_rest(depth: float, spans: int) -> tuple[float, float, float, float]:
    """(fairlead tension, anchor tension, touch-down point's distance from the anchor, wall time of
    the equilibrium start) of slidebeam's chain_scene_data."""
    import petsc4py

    petsc4py.init([])
    import slidebeam

    sim = slidebeam.Simulation(slidebeam.scene_from_dict(chain_scene_data(depth, spans)))
    outcome = sim.settle()
    if not outcome.converged:
        raise RuntimeError(f"the {depth} m chain's equilibrium start did not converge")
    f = {r.effect: np.asarray(r.force) for r in sim.reactions()}
    samples = sim.sample_beam("chain", samples_per_span=16)
    on_bed = samples["position"][samples["position"][:, 2] < -depth + 2e-3]
    return (float(np.linalg.norm(f["spherical[chain@end]"])), float(np.linalg.norm(f["spherical[chain@start]"])),
            float(on_bed[:, 0].max()), sim.settle_wall_time)


MOORDYN_CHAIN = """--------------------- MoorDyn Input File ------------------------------------
a chain of compare_mooring.py's CHAIN_CASES
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA         BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)        (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
chain      {d}   {m}        {EA}    -1.0        0          1.37   1.0    0.64    0.0
---------------------- POINT PROPERTIES --------------------------------
ID    Type      X       Y       Z       Mass   Volume  CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)   (m^3)   (m^2)  (-)
1     Fixed     0.0     0.0     {z}    0      0       0      0
2     Coupled   {x}     0.0     0.0     0      0       0      0
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)       (-)     (-)
1     chain      1        2         {L}       {n}      -
---------------------- OPTIONS -----------------------------------------
1.0e-4               dtM
1.0e6                kBot
1.0e4                cBot
{rho}               WtrDnsty
{depth}              WtrDpth
{g}              g
100.0                TmaxIC
1.0e-6               threshIC
--------------------- OUTPUTS --------------------------------------------
END
------------------------- need this line --------------------------------------
"""


def smooth_blend(u: float) -> tuple[float, float]:
    """10u^3 - 15u^4 + 6u^5 (the core's smooth ramp) and its rate d/du, u in [0, 1]."""
    return u**3 * (10.0 + u * (-15.0 + 6.0 * u)), 30.0 * u * u * (1.0 - u) ** 2


@contextlib.contextmanager
def c_stdout_silenced():
    """MoorDyn reports on the C library's stdout: send it to /dev/null for the block."""
    sys.stdout.flush()
    saved, quiet = os.dup(1), os.open(os.devnull, os.O_WRONLY)
    os.dup2(quiet, 1)
    try:
        yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)
        os.close(quiet)


def moordyn_chain_at_rest(depth: float, work: Path) -> tuple[float, float, float]:
    """(fairlead tension, anchor tension, wall time) of MoorDyn's own static initialisation of
    the case (its Python module), at MoorDyn's segments."""
    import time

    import moordyn  # type: ignore[import-not-found]

    span, length, segments = CHAIN_CASES[depth][:3]
    path = work / f"moordyn_chain_{int(depth)}.txt"
    path.write_text(MOORDYN_CHAIN.format(d=CHAIN_D, m=CHAIN_RHO_A, EA=CHAIN_EA, z=-depth, x=span, L=length,
                                         n=segments, rho=SEA, depth=depth, g=G))
    with c_stdout_silenced():
        started = time.perf_counter()
        system = moordyn.Create(str(path))
        moordyn.Init(system, [span, 0.0, 0.0], [0.0, 0.0, 0.0])
        wall = time.perf_counter() - started
        fh, fv, ah, av = moordyn.GetFASTtens(system, 1)
        moordyn.Close(system)
    return math.hypot(fh[0], fv[0]), math.hypot(ah[0], av[0]), wall


def chain_table(fine: int) -> None:
    """The three chain cases: slidebeam's equilibrium start (at MoorDyn's segments and `fine` times
    as many), the closed form (MooringLine), MoorPy's Catenary and MoorDyn's own static start where
    installed, against the quasi-static codes' tensions."""
    import tempfile

    from slidebeam.scene.catenary import MooringLine

    try:
        from moorpy.Catenary import catenary  # type: ignore[import-not-found]
    except ImportError:
        catenary = None
    try:
        import moordyn  # type: ignore[import-not-found] # noqa: F401
        have_moordyn = True
    except ImportError:
        have_moordyn = False
    if catenary is None or not have_moordyn:
        print("MoorPy or MoorDyn is not installed here: see this script's docstring to compare with them",
              file=sys.stderr)
    print("| depth, m | line | fairlead tension, kN | error | anchor tension, kN | error | touch-down from the anchor, m "
          "| wall, s |")
    print("|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as work:
        for depth, (span, length, segments, T_ref, A_ref) in CHAIN_CASES.items():
            print(f"| {depth:g} | quasi-static codes (MoorDyn's reference) | {T_ref:.1f} | | {A_ref:.1f} | | | |")

            def row(name: str, T: float, A: float, touchdown: str, wall: str) -> None:
                print(f"| {depth:g} | {name} | {T / 1e3:.1f} | {T / 1e3 / T_ref - 1:+.2%} | {A / 1e3:.1f} | "
                      f"{A / 1e3 / A_ref - 1:+.2%} | {touchdown} | {wall} |", flush=True)

            exact = MooringLine(span=span, height=depth, length=length, EA=CHAIN_EA, w=CHAIN_W)
            row("elastic catenary (MooringLine)", exact.fairlead_tension, exact.anchor_tension, f"{exact.touchdown:.1f}",
                "")
            if catenary is not None:
                fAH, fAV, fBH, fBV, info = catenary(span, depth, length, CHAIN_EA, CHAIN_W, CB=0.0, Tol=1e-10)
                row("MoorPy (Catenary)", math.hypot(fBH, fBV), math.hypot(fAH, fAV),
                    f"{float(info['LBot']) * (1.0 + abs(fAH) / CHAIN_EA):.1f}", "")
            if have_moordyn:
                T, A, wall = moordyn_chain_at_rest(depth, Path(work))
                row(f"MoorDyn 2.7, {segments} segments, static start", T, A, "", f"{wall:.2f}")
            for n in (segments, fine * segments):
                T, A, touchdown, wall = chain_at_rest(depth, n)
                row(f"slidebeam, {n} spans, equilibrium start", T, A, f"{touchdown:.1f}", f"{wall:.2f}")


MOORDYN_MOVING = """--------------------- MoorDyn Input File ------------------------------------
runs/cables/mooring_line.toml's chain (compare_mooring.py --moving)
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA         BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)        (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
chain      {d}   {m}        {EA}    -1.0        0          0.0    0.0    0.0     0.0
---------------------- POINT PROPERTIES --------------------------------
ID    Type      X       Y       Z       Mass   Volume  CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)   (m^3)   (m^2)  (-)
1     Fixed     0.0     0.0     -50.0   0      0       0      0
2     Coupled   200.0   0.0     0.0     0      0       0      0
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)       (-)     (-)
1     chain      1        2         220.0     {n}      -
---------------------- OPTIONS -----------------------------------------
{dtM}                dtM
{kbot}               kBot
{cbot}               cBot
1025.0               WtrDnsty
50.0                 WtrDpth
9.81                 g
RK4                  tScheme
200.0                TmaxIC
1.0e-6               threshIC
--------------------- OUTPUTS --------------------------------------------
END
------------------------- need this line --------------------------------------
"""
MOVE, MOVE_TIME, MOVING_END = 5.0, 10.0, 20.0  # the scene's fairlead: 5 m out over 10 s, held to 20 s


def slidebeam_moving(spans: int, sets: list[str], ancf: bool = False) -> dict:
    """runs/cables/mooring_line.toml at `spans` spans (ancf: the chain as an ANCF cable of as many
    elements, without the director beam's shear and torsion): the fairlead tension at 0, 10 and
    20 s and the time stepping's wall time (the equilibrium start apart)."""
    import time

    import petsc4py

    petsc4py.init([])
    import slidebeam

    scene = slidebeam.load_scene(ROOT / "runs" / "cables" / "mooring_line.toml",
                                 [f"beam.chain.spans={spans}", "output.xdmf=false", "output.every=1", *sets])
    if ancf:
        data = dict(scene.data)
        chain = data["beam"][0]
        section = chain["section"]
        data["beam"] = [{**chain, "formulation": "ancf",
                         "section": {"EA": section["EA"], "EI": section["EI2"], "rhoA": section["rhoA"]}}]
        scene = slidebeam.scene_from_dict(data)
    sim = slidebeam.Simulation(scene)
    sim.settle()
    tensions: dict[float, float] = {}

    def on_step(record) -> None:
        for t in (MOVE_TIME, MOVING_END):
            if abs(record.t - t) < 1e-9:
                f = {r.effect: np.asarray(r.force) for r in record.reactions}
                tensions[t] = float(np.linalg.norm(f["spherical[chain@end]"]))

    tensions[0.0] = float(np.linalg.norm({r.effect: np.asarray(r.force) for r in sim.reactions()}["spherical[chain@end]"]))
    started = time.perf_counter()
    outcome = sim.run_dynamic(on_step)
    wall = time.perf_counter() - started
    if not outcome.complete:
        raise RuntimeError(f"the mooring line's run did not finish: {outcome.message}")
    steps = len(sim.step_wall_times)
    return {"tension": tensions, "wall": wall, "steps": steps, "dt": scene.analysis.dt}


def moordyn_moving(segments: int, dtM: float, work: Path) -> dict | None:
    """The same line in MoorDyn (RK4, no drag or added mass, the bed as stiff as slidebeam's): the
    coupled fairlead moved by the same smooth ramp, coupled every 0.01 s. None if it blew up."""
    import time

    import moordyn  # type: ignore[import-not-found]

    d = 0.13790157544671897  # the scene's buoyancy diameter (the steel volume)
    path = work / f"moordyn_moving_{segments}_{dtM:g}.txt"
    path.write_text(MOORDYN_MOVING.format(d=d, m=117.24598880562183, EA=EA, n=segments, dtM=dtM, kbot=1e7 / d,
                                          cbot=0.0))
    try:
        with c_stdout_silenced():
            system = moordyn.Create(str(path))
            moordyn.Init(system, [200.0, 0.0, 0.0], [0.0, 0.0, 0.0])
            point = moordyn.GetPoint(system, 2)

            def tension() -> float:
                return math.sqrt(sum(f * f for f in moordyn.GetPointForce(point)))

            tensions = {0.0: tension()}
            dt = 0.01
            steps = int(round(MOVING_END / dt))
            started = time.perf_counter()
            for k in range(steps):
                t1 = (k + 1) * dt
                u = min(t1 / MOVE_TIME, 1.0)
                f, df = smooth_blend(u)
                x = 200.0 + MOVE * f
                v = MOVE / MOVE_TIME * df
                moordyn.Step(system, [x, 0.0, 0.0], [v, 0.0, 0.0], k * dt, dt)
                for t in (MOVE_TIME, MOVING_END):
                    if abs(t1 - t) < 1e-9:
                        tensions[t] = tension()
            wall = time.perf_counter() - started
            moordyn.Close(system)
    except Exception:  # MoorDyn raises on NaN states
        return None
    if not all(math.isfinite(T) and T < 1e7 for T in tensions.values()):
        return None
    return {"tension": tensions, "wall": wall}


def moving_table(spans: list[int], repeat: int) -> None:
    """The scene's moving line in slidebeam and, where installed, MoorDyn at equal segments and its
    largest stable step (from 2e-3 s down by factors of 0.8 until the run stays finite): fairlead
    tension at 0, 10 and 20 s and the time stepping's wall time (the median of `repeat` runs)."""
    import statistics
    import tempfile

    def median_of(run) -> dict:
        results = [run() for _ in range(repeat)]
        return {**results[-1], "wall": statistics.median(r["wall"] for r in results)}

    try:
        import moordyn  # type: ignore[import-not-found] # noqa: F401
        have_moordyn = True
    except ImportError:
        have_moordyn = False
        print("MoorDyn is not installed here: see this script's docstring to compare with it", file=sys.stderr)
    print("| code | segments | time step, s | fairlead tension at 0 s, kN | at 10 s | error | at 20 s | error | "
          "time stepping, s | / MoorDyn's |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as work:
        for n in spans:
            md = None
            if have_moordyn:
                dtM = 2e-3
                while md is None and dtM > 1e-5:
                    md = moordyn_moving(n, dtM, Path(work))
                    if md is None:
                        dtM *= 0.8
                if md is not None:
                    md = median_of(lambda: moordyn_moving(n, dtM, Path(work)))
            reuse = ["petsc.sb_jacobian_reuse=true"]
            runs = [("slidebeam, director beam, full Newton", median_of(lambda: slidebeam_moving(n, []))),
                    ("slidebeam, director beam, modified Newton", median_of(lambda: slidebeam_moving(n, reuse))),
                    ("slidebeam, ANCF cable, full Newton", median_of(lambda: slidebeam_moving(n, [], ancf=True))),
                    ("slidebeam, ANCF cable, modified Newton",
                     median_of(lambda: slidebeam_moving(n, reuse, ancf=True))),
                    ("slidebeam, ANCF cable, modified Newton, dt = 0.1 s",
                     median_of(lambda: slidebeam_moving(n, [*reuse, "analysis.dt=0.1"], ancf=True))),
                    ("reference: slidebeam, ANCF cable, modified Newton",
                     {**slidebeam_moving(4 * n, [*reuse, "analysis.dt=0.0125"], ancf=True), "segments": 4 * n})]
            if md is not None:
                runs.append(("MoorDyn 2.7, RK4", {**md, "dt": dtM}))
            ref = runs[-2 if md is not None else -1][1]["tension"]
            for name, r in runs:
                T = r["tension"]
                ratio = f"{r['wall'] / md['wall']:.2f}" if md is not None else ""
                print(f"| {name} | {r.get('segments', n)} | {r['dt']:.3g} | {T[0.0] / 1e3:.2f} | "
                      f"{T[MOVE_TIME] / 1e3:.2f} | {T[MOVE_TIME] / ref[MOVE_TIME] - 1:+.1e} | "
                      f"{T[MOVING_END] / 1e3:.2f} | {T[MOVING_END] / ref[MOVING_END] - 1:+.1e} | {r['wall']:.2f} | "
                      f"{ratio} |", flush=True)


# Lowe & Langley's flexible jumper (OMAE 2006; MoorDyn's tests/lowe_and_langley_2006.cpp and
# tests/Mooring/lowe_and_langley_2006/line.txt): 170 m of 0.396 m hose, 165 kg/m, EA = 5e8 N,
# EI = 120.8e3 N m^2, in water of 1000 kg/m^3 (g = 9.807), pinned at (-100, 0, -55) and (0, 0, -5);
# static end forces of the reference, kN: at the top and at the bottom.
JUMPER = {"length": 170.0, "d": 0.396, "rhoA": 165.0, "EA": 5e8, "EI": 120.8e3, "rho": 1000.0, "g": 9.807,
          "bottom": (-100.0, -55.0), "top": (0.0, -5.0)}
JUMPER_TOP, JUMPER_BOTTOM = (11.40, 0.0, 45.71), (-11.40, 0.0, 24.04)


def catenary_through(span: float, rise: float, L0: float, EA: float, w: float) -> tuple[float, float]:
    """(H, V) at the lower end of the elastic catenary of unstretched length L0 from there to a
    point `span` further and `rise` higher (Newton on catenary_end)."""
    from slidebeam.scene.catenary import catenary_end

    H, V = 0.1 * w * L0, 0.5 * w * L0
    for _ in range(100):
        x, z = catenary_end(L0, H, V, EA, w)
        r = np.array([x - span, z - rise])
        if abs(r).sum() < 1e-12 * (span + abs(rise)):
            break
        J = np.empty((2, 2))
        for k, (dH, dV) in enumerate(((1e-7 * H, 0.0), (0.0, 1e-7 * w * L0))):
            xp, zp = catenary_end(L0, H + dH, V + dV, EA, w)
            J[:, k] = ((xp - x) / (dH or dV), (zp - z) / (dH or dV))
        dH, dV = np.linalg.solve(J, -r)
        H, V = max(H + dH, 0.5 * H), V + dV
    return H, V


def jumper_scene_data(spans: int = 68) -> dict:
    """The jumper as a scene: drawn along its elastic catenary without bending stiffness, given by
    its unstretched length; the equilibrium start bends it (pinned ends)."""
    from slidebeam.scene.catenary import catenary_end

    j = JUMPER
    w = (j["rhoA"] - j["rho"] * math.pi / 4 * j["d"] ** 2) * j["g"]
    (x0, z0), (x1, z1) = j["bottom"], j["top"]
    H, V = catenary_through(x1 - x0, z1 - z0, j["length"], j["EA"], w)
    points = []
    for s in np.linspace(0.0, j["length"], 41):
        x, z = catenary_end(j["length"], H, V, j["EA"], w, s)
        points.append([x0 + x, 0.0, z0 + z])
    points[-1] = [x1, 0.0, z1]
    E_over_G = 2.6
    return {
        "scene": {"name": "jumper"},
        "analysis": {"type": "dynamic", "start": "equilibrium", "dt": 0.01, "t_end": 1e-9},
        "beam": [{"name": "jumper", "polyline": points, "unstretched_length": j["length"], "spans": spans,
                  "section": {"EA": j["EA"], "kGA": 0.9 * j["EA"] / E_over_G, "GJ": j["EI"] / 1.3,
                              "EI2": j["EI"], "EI3": j["EI"], "rhoA": j["rhoA"], "rhoI2": 1.0, "rhoI3": 1.0}}],
        "support": [{"type": "spherical", "beam": "jumper", "at": "start"},
                    {"type": "spherical", "beam": "jumper", "at": "end"}],
        "gravity": {"g": [0.0, 0.0, -j["g"]]},
        "buoyancy": [{"beam": "jumper", "density": j["rho"], "diameter": j["d"], "surface": [0.0, 0.0, 0.0]}],
        "output": {"xdmf": False},
    }


def jumper_at_rest(spans: int) -> tuple[np.ndarray, np.ndarray, float]:
    """(force of the supports on the jumper at the top and at the bottom, N; wall time of the start)
    after slidebeam's equilibrium start: the supports' reactions, with the reference's signs."""
    import petsc4py

    petsc4py.init([])
    import slidebeam

    sim = slidebeam.Simulation(slidebeam.scene_from_dict(jumper_scene_data(spans)))
    if not sim.settle().converged:
        raise RuntimeError("the jumper's equilibrium start did not converge")
    f = {r.effect: np.asarray(r.force) for r in sim.reactions()}
    return f["spherical[jumper@end]"], f["spherical[jumper@start]"], sim.settle_wall_time


def jumper_table(spans: list[int]) -> None:
    print("| line | top: horizontal, kN | vertical, kN | bottom: horizontal, kN | vertical, kN | largest error, kN |")
    print("|---|---|---|---|---|---|")
    print(f"| Lowe & Langley (MoorDyn's reference) | {JUMPER_TOP[0]:.2f} | {JUMPER_TOP[2]:.2f} | "
          f"{JUMPER_BOTTOM[0]:.2f} | {JUMPER_BOTTOM[2]:.2f} | |")
    for n in spans:
        top, bottom, _ = jumper_at_rest(n)
        err = max(abs(top[0] / 1e3 - JUMPER_TOP[0]), abs(top[2] / 1e3 - JUMPER_TOP[2]),
                  abs(bottom[0] / 1e3 - JUMPER_BOTTOM[0]), abs(bottom[2] / 1e3 - JUMPER_BOTTOM[2]))
        print(f"| slidebeam, {n} spans | {top[0] / 1e3:.2f} | {top[2] / 1e3:.2f} | {bottom[0] / 1e3:.2f} | "
              f"{bottom[2] / 1e3:.2f} | {err:.2f} |", flush=True)


# the friction runs: from 175 m (1.6 kN of horizontal tension) out to 205 m over 60 s, 30 s at rest
START_SPAN, PULL, RAMP, SETTLE = 175.0, 30.0, 60.0, 30.0
LAID_CORNER = 5.0  # m: the radius of the slack chain's turn from the bed up to the fairlead (laid_slack)


# Lowe & Langley's dynamic cases 1-3 (MoorDyn's tests/lowe_and_langley_2006.cpp): the top moved
# 10 m along x, y or z at a period of 27 s, faded in over the first period by the smooth ramp
# 10u^3 - 15u^4 + 6u^5; the reference's top tension over the 80 s after the ramp, kN
# (tests/data/lowe_and_langley_2006/case<k>.csv, copied from MoorDyn's repository, BSD-3-Clause).
JUMPER_AMPLITUDE, JUMPER_PERIOD, JUMPER_COMPARED = 10.0, 27.0, 80.0
JUMPER_DATA = ROOT / "tests" / "data" / "lowe_and_langley_2006"
JUMPER_WATER = {"cd_normal": 1.0, "cd_tangential": 0.0, "ca_normal": 1.0, "ca_tangential": 0.0}  # Cd, CdAx, Ca, CaAx


def jumper_moving_scene_data(case: int, spans: int, dt: float, added_mass: bool = True, ancf: bool = False) -> dict:
    """The jumper's dynamic case 1, 2 or 3: from its equilibrium start, the top moved along x, y or
    z; drag and added mass as the reference's (Cd = Ca = 1 across, none along); modified Newton.
    A director beam, or an ANCF cable (its EA, EI and mass; no shear, torsion or rotary inertia)."""
    j = JUMPER
    data = jumper_scene_data(spans)
    if ancf:
        data["beam"] = [{**data["beam"][0], "formulation": "ancf",
                         "section": {"EA": j["EA"], "EI": j["EI"], "rhoA": j["rhoA"]}}]
    data["analysis"] = {**data["analysis"], "t_end": JUMPER_PERIOD + JUMPER_COMPARED, "dt": dt}
    displacement = [0.0, 0.0, 0.0]
    displacement[case - 1] = JUMPER_AMPLITUDE
    data["support"][1]["motion"] = {"displacement": displacement, "time_function": {
        "type": "sine", "frequency": 1.0 / JUMPER_PERIOD, "ramp": JUMPER_PERIOD}}
    water = {**JUMPER_WATER, **({} if added_mass else {"ca_normal": 0.0})}
    data["drag"] = [{"beam": "jumper", "density": j["rho"], "diameter": j["d"], **water}]
    data["petsc"] = {"sb_jacobian_reuse": True}
    data["output"] = {"xdmf": False}
    return data


def jumper_moving(case: int, spans: int, dt: float, added_mass: bool = True, ancf: bool = False) -> dict:
    """The reference's times (after the ramp) and top tensions, slidebeam's top tension there (kN),
    the run's wall time, steps and Newton iterations."""
    import petsc4py

    petsc4py.init([])
    import time

    import slidebeam

    sim = slidebeam.Simulation(slidebeam.scene_from_dict(jumper_moving_scene_data(case, spans, dt, added_mass, ancf)))
    start = time.perf_counter()
    run = sim.run_dynamic()
    wall = time.perf_counter() - start
    if not run.complete:
        raise RuntimeError(f"the jumper's case {case} did not run to its end: {run.message}")
    records = run.records
    t = np.array([r.t for r in records])
    top = np.array([np.linalg.norm(r.reactions[1].force) for r in records]) / 1e3
    ref = np.loadtxt(JUMPER_DATA / f"case{case}.csv", delimiter=",")
    return {"t": ref[:, 0], "reference": ref[:, 1], "slidebeam": np.interp(ref[:, 0] + JUMPER_PERIOD, t, top),
            "wall": wall, "steps": run.steps, "newton": run.newton_iterations}


# Lowe & Langley's jumper as MoorDyn's test runs it (tests/Mooring/lowe_and_langley_2006/line.txt;
# its internal damping, BA = -0.5: half the critical damping of a segment's axial mode)
MOORDYN_JUMPER = """MoorDyn input file for a flexible jumper (Lowe and Langley, 2006)
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam     Mass/m     EA         BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)      (kg/m)     (N)        (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
main       0.396    165.0      500.0e6    -0.5        120.8e3    1.0    {ca}    0.0     0.0
---------------------- CONNECTION PROPERTIES --------------------------------
ID    Type      X       Y       Z       Mass    Volume      CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)    (m^3)       (m^2)  (-)
1     Fixed     -100    0       -55     0       0           0      0
2     Coupled   0       0       -5      0       0           0      0
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)       (-)     (-)
1      main      1        2         170       {n}       -
---------------------- OPTIONS -----------------------------------------
{dtM}         dtM           Model time step (s)
3.0e6         kBot          bottom stiffness (Pa/m)
3.0e5         cBot          bottom damping (Pa-s/m)
100           WtrDpth       water depth (m)
1000.0        WtrDnsty      water density (kg/m^3)
9.807         g             gravity (m/s^2)
midpoint5     tScheme       Time integration scheme
5.0           CdScaleIC     Initial Condition generation drag factor
30            TmaxIC        Initial Condition generation maximum time (s)
1.0           dtIC          Initial Condition generation convergence tests (s)
5e-3          threshIC      Initial Condition generation convergence threshold
0             writeLog      Write a log file
1       disableOutTime
------------------------- need this line --------------------------------------
"""


def moordyn_jumper(case: int, segments: int, dtM: float, work: Path) -> dict | None:
    """The jumper's case in MoorDyn (the scheme of its test, midpoint5), as its own test drives it:
    the coupled top moved every 5 ms; its top tension at the reference's times. None if it blew
    up (a NaN, or a tension ten times the reference's largest)."""
    import time

    import moordyn  # type: ignore[import-not-found]

    path = work / f"moordyn_jumper_{segments}_{dtM:g}.txt"
    path.write_text(MOORDYN_JUMPER.format(n=segments, dtM=dtM, ca=JUMPER_WATER["ca_normal"]))
    ref = np.loadtxt(JUMPER_DATA / f"case{case}.csv", delimiter=",")
    try:
        with c_stdout_silenced():
            system = moordyn.Create(str(path))
            r0 = [0.0, 0.0, -5.0]
            moordyn.Init(system, r0, [0.0, 0.0, 0.0])
            line = moordyn.GetLine(system, 1)
            dt, T, A = 0.005, JUMPER_PERIOD, JUMPER_AMPLITUDE
            steps = int(round((T + JUMPER_COMPARED) / dt))
            times, top = [], []
            started = time.perf_counter()
            for k in range(steps):
                t1 = (k + 1) * dt
                u = min(t1 / T, 1.0)
                fade, dfade = smooth_blend(u)
                dfade /= T
                w = 2.0 * math.pi / T
                r, v = list(r0), [0.0, 0.0, 0.0]
                r[case - 1] += A * fade * math.sin(w * t1)
                v[case - 1] = A * (dfade * math.sin(w * t1) + fade * w * math.cos(w * t1))
                moordyn.Step(system, r, v, k * dt, dt)
                if t1 >= T - 1e-9:
                    times.append(t1 - T)
                    top.append(np.linalg.norm(moordyn.GetLineNodeForce(line, segments)) / 1e3)
            wall = time.perf_counter() - started
            moordyn.Close(system)
    except Exception:  # MoorDyn raises on NaN states
        return None
    mine = np.interp(ref[:, 0], times, top)
    if not np.all(np.isfinite(mine)) or mine.max() > 10.0 * ref[:, 1].max():
        return None
    return {"t": ref[:, 0], "reference": ref[:, 1], "moordyn": mine, "wall": wall}


ANCF_STEPS = (0.05, 0.1, 0.2)  # --jumper-moving: the jumper as an ANCF cable at these steps


def jumper_moving_table(spans: list[int], dts: list[float]) -> None:
    import tempfile

    try:
        import moordyn  # noqa: F401  # type: ignore[import-not-found]

        moordyn_ok = True
    except ImportError:
        moordyn_ok = False
        print("MoorDyn is not installed here: see this script's docstring to compare with it", file=sys.stderr)
    work = Path(tempfile.mkdtemp(prefix="jumper_"))
    print("| case: top moved along | line | dt, s | added mass | top tension, kN: reference | computed | "
          "largest error, kN | mean error, kN | wall, s | Newton per step |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for case in (1, 2, 3):
        runs = [(n, dt, True, False) for n in spans for dt in dts] + [(spans[0], dts[0], False, False)]
        runs += [(spans[0], dt, True, True) for dt in ANCF_STEPS]
        for n, dt, added, ancf in runs:
            r = jumper_moving(case, n, dt, added, ancf)
            err = r["slidebeam"] - r["reference"]
            line = f"slidebeam, {n} {'ANCF elements' if ancf else 'spans'}"
            print(f"| {case}: {'xyz'[case - 1]} | {line} | {dt:g} | {'Ca = 1' if added else 'none'} | "
                  f"{r['reference'].min():.2f}-{r['reference'].max():.2f} | "
                  f"{r['slidebeam'].min():.2f}-{r['slidebeam'].max():.2f} | {np.abs(err).max():.2f} | "
                  f"{err.mean():+.2f} | {r['wall']:.1f} | {r['newton'] / r['steps']:.1f} |", flush=True)
        if moordyn_ok:
            for dtM in (1e-3, 2e-3):  # its test's step, and twice that
                m = moordyn_jumper(case, 68, dtM, work)
                if m is None:
                    print(f"| {case}: {'xyz'[case - 1]} | MoorDyn, 68 segments | {dtM:g} | Ca = 1 | | blew up | | | | |")
                    continue
                err = m["moordyn"] - m["reference"]
                print(f"| {case}: {'xyz'[case - 1]} | MoorDyn, 68 segments | {dtM:g} | Ca = 1 | "
                      f"{m['reference'].min():.2f}-{m['reference'].max():.2f} | "
                      f"{m['moordyn'].min():.2f}-{m['moordyn'].max():.2f} | {np.abs(err).max():.2f} | "
                      f"{err.mean():+.2f} | {m['wall']:.1f} | |", flush=True)


def jumper_figure(path: str, spans: int, dt: float) -> None:
    """The three cases' top tension over time, the reference's and slidebeam's, in one figure."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    for case, ax in zip((1, 2, 3), axes):
        r = jumper_moving(case, spans, dt)
        dry = jumper_moving(case, spans, dt, added_mass=False)
        ax.plot(r["t"], r["reference"], color="k", lw=2.5, alpha=0.35, label="Lowe & Langley (2006)")
        ax.plot(r["t"], r["slidebeam"], color="C0", lw=1.0, label=f"slidebeam, {spans} spans, dt = {dt:g} s")
        ax.plot(dry["t"], dry["slidebeam"], color="C3", lw=0.8, ls="--", label="slidebeam without added mass")
        ax.set_ylabel("top tension, kN")
        ax.set_title(f"case {case}: the top moved 10 m along {'xyz'[case - 1]} at a period of 27 s", fontsize=10)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time after the ramp, s")
    fig.legend(*axes[0].get_legend_handles_labels(), loc="lower center", ncol=3, fontsize=8)
    fig.tight_layout(rect=(0.0, 0.035, 1.0, 1.0))
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


def laid_slack(sink: float, corner: float = LAID_CORNER) -> tuple[list[list[float]], float]:
    """The chain laid slack as drawn: along the seabed from the anchor (sunk `sink` into the bed),
    round a quarter circle of radius `corner` and straight up to the fairlead, its drawn length
    LENGTH exactly (the circle's chords included), so that it starts unstretched. Returns the
    polyline and the fairlead's x."""
    arc = [(corner * math.sin(t), corner * (1.0 - math.cos(t))) for t in np.linspace(0.0, math.pi / 2, 9)]
    chords = sum(math.dist(arc[i], arc[i + 1]) for i in range(len(arc) - 1))
    along = LENGTH - chords - (DEPTH + sink - corner)  # the part on the bed
    points = [[0.0, 0.0, -DEPTH - sink]] + [[along + u, 0.0, -DEPTH - sink + v] for u, v in arc]
    points.append([along + corner, 0.0, 0.0])
    return points, along + corner


def pulled_scene(mu: float, spans: int, ramp: float = RAMP, settle: float = SETTLE, dt: float | None = None,
                 stick: float = 10.0, laid: bool = False, ancf: bool = False):
    """The scene's chain on a seabed with friction mu: from the frictionless equilibrium start with
    the fairlead at START_SPAN (1.6 kN of horizontal tension), pulled out by PULL over `ramp`
    seconds and left to settle for `settle` more (the bed damped, the chain's swing damped by
    mass-proportional damping, which vanishes at rest; stick: the sticking springs' stiffness
    over the bed's). A line pulled out mobilises the seabed's
    friction against the pull along its grounded part, as MoorPy's model of seabed friction
    assumes, wherever its tension grew. laid: the chain starts instead laid slack on the bed
    (laid_slack: no tension along the bed), at rest as drawn, and is pulled out from there to the
    same fairlead, so that no tension of an earlier state stays at the anchor. ancf: the chain as an
    ANCF cable (its EA, EI and mass)."""
    import slidebeam
    from slidebeam.scene.catenary import MooringLine

    scene = slidebeam.load_scene(ROOT / "runs" / "cables" / "mooring_line.toml",
                                 [f"beam.chain.spans={spans}", f"analysis.t_end={ramp + settle}", "output.xdmf=false",
                                  "output.every=20", *([f"analysis.dt={dt}"] if dt else [])])
    data = dict(scene.data)
    # the anchor where the chain rests, sunk w / k into the bed: pinned at the bed's surface it
    # would hold the chain's end up and carry the weight of its first 0.3 m, which the bed's
    # friction then lacks (mu times 312 N at the anchor; the closed form's anchor carries none)
    sink = W / data["contact"][0]["stiffness"]
    if laid:
        points, fairlead_x = laid_slack(sink)
        # the drawing stress free: its corner's bend stays in the chain where it hangs (3e-4 of the
        # tensions); a straight stress-free state would start the corner springing straight, and the
        # start would cut a thousand steps (docs/verification.md)
        beam = {key: v for key, v in data["beam"][0].items() if key != "unstretched_length"}
        data["analysis"] = {**data["analysis"], "start": "reference"}
    else:
        # drawn along the frictionless catenary at START_SPAN (the start then has little to do)
        start = MooringLine(span=START_SPAN, height=DEPTH, length=LENGTH, EA=EA, w=W)
        H, hanging = start.H, start.suspended_length
        points = [[0.0, 0.0, -DEPTH - sink], [start.touchdown, 0.0, -DEPTH - sink]]
        for u in np.linspace(0.0, hanging, 25)[1:]:
            a = W * u / H
            points.append([start.touchdown + H / W * math.asinh(a) + H * u / EA, 0.0,
                           -DEPTH + H / W * (math.sqrt(1.0 + a * a) - 1.0) + W * u * u / (2.0 * EA)])
        points[-1] = [START_SPAN, 0.0, 0.0]
        fairlead_x = START_SPAN
        beam = data["beam"][0]
    data["beam"] = [{**beam, "polyline": points}]
    fairlead = data["support"][1]
    data["support"] = [data["support"][0], {**fairlead, "motion": {
        "displacement": [START_SPAN + PULL - fairlead_x, 0.0, 0.0],
        "time_function": {"type": "smooth_ramp", "t0": 0.0, "t1": ramp}}}]
    k = data["contact"][0]["stiffness"]
    rhoA = data["beam"][0]["section"]["rhoA"]
    # sticking points held 10x stiffer than the bed's default: a point gives mu N / k_t before it
    # slips, and the chain next to the anchor, which the pull stretches least, would not slip
    # over its first 0.46 m at k_t = k (mu = 0.5: 1.4e-3 of H less friction than the closed
    # form's rigid stick), 0.05 m at 10 k; the stiffer springs take 3x the Newton iterations
    data["contact"] = [{**data["contact"][0], "mu": mu, "damping": 2 * 0.3 * math.sqrt(k * rhoA),
                        "tangential_stiffness": stick * k}]
    data["damping"] = [{**data["damping"][0], "mass_proportional": 1.0}]
    if ancf:  # (a cable's stress-free state is straight: the drawing is only where it starts)
        section = data["beam"][0]["section"]
        data["beam"] = [{**data["beam"][0], "formulation": "ancf", "unstretched_length": LENGTH,
                         "section": {"EA": section["EA"], "EI": section["EI2"], "rhoA": section["rhoA"]}}]
    return slidebeam.scene_from_dict(data)


def line_at_rest(sim, record) -> tuple[float, float, float]:
    """(fairlead tension, anchor's horizontal pull, chain on the seabed in unstretched m) of a
    record of the scene's chain. The length on the seabed is the bed's force over the submerged
    weight per metre: where the chain lies the bed carries its weight (the anchor, where it
    rests, carries none). Read off the centre line instead (where it lies within 2 mm of the
    bed) it would depend on the threshold: the catenary rises 2 mm within sqrt(2 H / w 2 mm) =
    0.66 m of its touch-down point."""
    f = {r.effect: np.asarray(r.force) for r in record.reactions}
    bed = record.outputs[sim.output_labels().index("plane_contact[chain].force.z")]
    return float(np.linalg.norm(f["spherical[chain@end]"])), float(-f["spherical[chain@start]"][0]), float(bed / W)


def pulled_line(mu: float, spans: int, laid: bool = False) -> tuple[float, float, float, float]:
    """line_at_rest of pulled_scene at its end, and the run's wall time."""
    import time

    import petsc4py

    petsc4py.init([])
    import slidebeam

    started = time.perf_counter()
    sim = slidebeam.Simulation(pulled_scene(mu, spans, laid=laid))
    record = sim.run_dynamic().records[-1]
    return (*line_at_rest(sim, record), time.perf_counter() - started)


def friction_table(spans: list[int], coefficients: list[float], laid: bool = False) -> None:
    """The pulled-out line against the closed form with seabed friction (MooringLine, friction) and
    MoorPy's Catenary with CB = mu; laid: also the line laid slack before the pull (pulled_scene)."""
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
    # the start's tension along the bed: the chain next to the anchor keeps it where the pull,
    # falling by mu w per metre from the touch-down point, never reaches it
    H0 = MooringLine(span=START_SPAN, height=DEPTH, length=LENGTH, EA=EA, w=W).H
    for mu in coefficients:
        exact = MooringLine(span=span, height=DEPTH, length=LENGTH, EA=EA, w=W, friction=mu)
        ref = (exact.fairlead_tension, exact.anchor_tension, LENGTH - exact.suspended_length)
        print(f"| {mu} | MooringLine | {ref[0]:.2f} | | {ref[1]:.2f} | | {ref[2]:.2f} | |")
        if ref[1] < H0:
            ref = (ref[0], H0, ref[2])
            print(f"| {mu} | MooringLine, the start's {H0:.2f} N kept at the anchor | | | {H0:.2f} | | | |")
        if catenary is not None:
            fAH, _, fBH, fBV, info = catenary(span, DEPTH, LENGTH, EA, W, CB=mu, Tol=1e-10)
            print(f"| {mu} | MoorPy (Catenary, CB = {mu}) | {math.hypot(fBH, fBV):.2f} | | {fAH:.2f} | | "
                  f"{float(info['LBot']):.2f} | |")
        for n in spans:
            T, H, bed, wall = pulled_line(mu, n)
            print(f"| {mu} | slidebeam, {n} spans | {T:.2f} | {T / ref[0] - 1:+.1e} | {H:.2f} | "
                  f"{(H - ref[1]) / exact.H:+.1e} | {bed:.2f} | {wall:.1f} |", flush=True)
        for n in spans if laid else []:  # no earlier tension kept: against the closed form itself
            T, H, bed, wall = pulled_line(mu, n, laid=True)
            print(f"| {mu} | slidebeam, {n} spans, laid slack first | {T:.2f} | "
                  f"{T / exact.fairlead_tension - 1:+.1e} | {H:.2f} | {(H - exact.anchor_tension) / exact.H:+.1e} | "
                  f"{bed:.2f} | {wall:.1f} |", flush=True)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--spans", type=int, nargs="+", default=[110, 220], help="meshes of the chain (default 110 220)")
    p.add_argument("--friction", type=float, nargs="*",
                   help="seabed friction coefficients: the line pulled out from 175 m to 205 m, then at rest, "
                        "against the closed form with friction (e.g. --friction 0 0.1 0.5 1.5)")
    p.add_argument("--laid", action="store_true",
                   help="--friction: also the line laid slack on the bed first (from a fairlead 172 m out), "
                        "so that no tension of a start stays at the anchor")
    p.add_argument("--chains", action="store_true",
                   help="the quasi-static chain cases MoorDyn validates against (50, 200 and 600 m deep)")
    p.add_argument("--moving", action="store_true",
                   help="the scene's line moved by its fairlead, slidebeam and MoorDyn side by side (--spans)")
    p.add_argument("--jumper", action="store_true", help="Lowe & Langley's jumper at rest (--spans)")
    p.add_argument("--jumper-moving", action="store_true",
                   help="Lowe & Langley's jumper under its top's 10 m / 27 s motions (--spans, --dt)")
    p.add_argument("--dt", type=float, nargs="+", default=[0.05], help="--jumper-moving: time steps (default 0.05)")
    p.add_argument("--figure", help="--jumper-moving: draw the three cases into this file (first of --spans, --dt)")
    p.add_argument("--repeat", type=int, default=3, help="--moving: runs of each, the median wall time (default 3)")
    args = p.parse_args()
    if args.jumper_moving:
        if args.figure:
            jumper_figure(args.figure, args.spans[0], args.dt[0])
        else:
            jumper_moving_table(args.spans, args.dt)
        return 0
    if args.jumper:
        jumper_table(args.spans)
        return 0
    if args.moving:
        moving_table(args.spans, args.repeat)
        return 0
    if args.chains:
        chain_table(2)
        return 0
    if args.friction:
        friction_table(args.spans, args.friction, args.laid)
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
