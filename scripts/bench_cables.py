#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The cable benchmark: time steps of the cable scenes users run, with the Newton variant chosen
by cost (the default) against full Newton (-sb_jacobian_reuse false) and modified Newton
(-sb_jacobian_reuse). Per scene (the rope scenes, the multibody crane and the rockfall net) and
variant: ms per step (summary.json stepping_time_s / steps,
median of --repeat runs), Newton iterations, Jacobians and rejected steps per step, and the share
of the Jacobian assembly in the run. For the swings (runs/cables/cable_swing.toml, the rope as a
director beam of 40 spans; runs/cables/cable_swing_ancf.toml, as an ANCF cable of 16 elements,
and of 40) also their accuracy: the first sideways frequency fitted to the tracked midpoint's
motion against the exact linear value 1.579505 rad/s, and the support tension of the static start
against the elastic catenary (Irvine) of the same cable. Time it only on an otherwise idle machine.

    scripts/bench_cables.py                      # every scene, 3 runs each
    scripts/bench_cables.py --repeat 1 --quick   # the swings shortened to 10.5 s
    scripts/bench_cables.py runs/cables/capstan.toml --set contact.0.mu=0   # a scene, changed

Side by side with MoorDyn (optional; the project does not depend on it): where the Python running
this script imports `moordyn`, the swing is also run by MoorDyn on the same cable (40 lumped-mass
segments, RK4 at dtM = 8e-4 s, its largest stable step there; bending stiffness, no water, no
damping), and a second table gives both codes' time for the swing, their errors against the
exact frequency and the catenary tension, and slidebeam's time over MoorDyn's. MoorDyn comes from
PyPI into a throwaway venv on Debian's Python (which keeps petsc4py visible):

    /usr/bin/python3 -m venv --system-site-packages /tmp/moordyn-venv
    /tmp/moordyn-venv/bin/pip install moordyn==2.7.2
    /tmp/moordyn-venv/bin/python scripts/bench_cables.py --repeat 3 runs/cables/cable_swing.toml \\
        runs/cables/cable_swing_ancf.toml
"""
from __future__ import annotations

import argparse
import csv
import dataclasses
import json
import math
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SWING = "runs/cables/cable_swing.toml"
SWING_ANCF = "runs/cables/cable_swing_ancf.toml"
# the swings' models, for the side-by-side
SWINGS = {SWING: "director beam, 40 spans, energy-momentum", SWING_ANCF: "ANCF cable, {spans} elements, energy-momentum"}
# the Newton variant each swing scene sets (its row in the side-by-side)
OWN_VARIANT = {SWING: "chosen by cost", SWING_ANCF: "modified Newton"}
SCENES = [(SWING, []), (SWING_ANCF, []), (SWING_ANCF, ["beam.0.spans=40"]), ("runs/cables/zip_line.toml", []), ("runs/cables/hanging_rope.toml", ["analysis.t_end=0.2"]),
          ("runs/effects/ropeway.toml", ["analysis.t_end=0.4"]), ("runs/effects/moving_anchor.toml", []),
          ("runs/cables/ropeway.toml", ["analysis.t_end=0.2"]), ("runs/multibody/crane.toml", []),
          ("runs/multibody/rockfall_net.toml", ["analysis.t_end=0.1"])]
VARIANTS = [("chosen by cost", ["-sb_newton_by_cost"]), ("full Newton", ["-sb_jacobian_reuse", "false"]),
            ("modified Newton", ["-sb_jacobian_reuse"])]
EXACT_OMEGA = 1.579505  # rad/s, the swing's first out-of-plane mode (linear theory)


def run(scene: str, sets: list[str], petsc: list[str], out: Path) -> dict:
    cmd = [str(ROOT / "scripts" / "slidebeam"), "run", str(ROOT / scene), "--out", str(out), "-q",
           "--set", "output.xdmf=false", *[a for s in sets for a in ("--set", s)], "--", *petsc]
    subprocess.run(cmd, check=True, capture_output=True, text=True)
    return json.loads((out / "summary.json").read_text())


def assembly_share(summary: dict) -> float:
    """Share of the run in assembly: the cost table's effect rows, residuals and Jacobians together."""
    return sum(c["share"] for c in summary.get("cost", []) if c["phase"].startswith("assembly"))


def swing_frequency(history: Path) -> float:
    """omega of the tracked midpoint's sideways (y) motion in slidebeam's history.csv."""
    rows = list(csv.DictReader(history.open()))
    return fit_frequency([float(r["t"]) for r in rows], [float(r["cable@50.3.y"]) for r in rows])


def fit_frequency(times: list[float], ys: list[float]) -> float:
    """omega of a sideways (y) motion after the support stopped (t > 1 s): the least-squares fit
    of a + b sin(omega t) + c cos(omega t) plus a sine and cosine at the strongest higher mode of
    the spectrum (the third symmetric mode, at 3x the frequency, rides on the first: zero
    crossings were off by 1e-3), omega refined on a grid about the peak."""
    import numpy as np

    t, y = np.asarray(times), np.asarray(ys)
    keep = t > 1.0
    t, y = t[keep], y[keep]
    if len(t) < 16:
        return float("nan")
    spectrum = np.abs(np.fft.rfft((y - y.mean()) * np.hanning(len(y))))
    omegas = 2 * math.pi * np.fft.rfftfreq(len(y), t[1] - t[0])
    peak = omegas[1 + int(np.argmax(spectrum[1:]))]
    above = omegas > 2 * peak  # the strongest higher mode, fitted alongside
    other = omegas[above][int(np.argmax(spectrum[above]))]

    def misfit(w: float) -> float:
        A = np.column_stack([np.ones_like(t), np.sin(w * t), np.cos(w * t), np.sin(other * t), np.cos(other * t)])
        c, *_ = np.linalg.lstsq(A, y, rcond=None)
        return float(np.linalg.norm(A @ c - y))

    lo, hi = 0.9 * peak, 1.1 * peak
    for _ in range(4):  # grids of 201 points, each 20x finer about the best
        grid = np.linspace(lo, hi, 201)
        best = grid[int(np.argmin([misfit(w) for w in grid]))]
        half = 5 * (hi - lo) / 200
        lo, hi = best - half, best + half
    return float(best)


def catenary_tension(L0: float = 100.6, span: float = 100.0, w: float = 9.81, EA: float = 1.0e7) -> float:
    """Support tension of a level elastic catenary (Irvine): H from
    span = H L0 / EA + H / w (asinh(V / H) - asinh((V - W) / H)), V = W / 2, by bisection."""
    W = w * L0
    V = W / 2

    def gap(H: float) -> float:
        return H * L0 / EA + H / w * (math.asinh(V / H) - math.asinh((V - W) / H)) - span

    lo, hi = 1.0, 1.0e6
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if gap(lo) * gap(mid) <= 0:
            hi = mid
        else:
            lo = mid
    H = 0.5 * (lo + hi)
    return math.hypot(H, V)


MOORDYN_INPUT = """--------------------- MoorDyn Input File ------------------------------------
slidebeam's runs/cables/cable_swing.toml: 100.6 m, 1 kg/m, EA 1e7 N, EI 10 N m^2, in air
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA     BA/-zeta    EI    Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)    (N-s/-)    (N-m^2) (-)   (-)    (-)     (-)
cable      0.01    1.0        1.0e7  0.0         10.0  0.0    0.0    0.0     0.0
---------------------- POINTS --------------------------------
ID  Attachment  X      Y     Z      M      V        CdA   CA
(#)   (-)       (m)   (m)   (m)    (kg)   (m^3)   (m^2)  (-)
1     Fixed      0     0     0      0      0        0     0
2     Coupled    100   0     0      0      0        0     0
---------------------- LINES --------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)         (-)     (-)
1     cable      1        2         100.6       {segments}       -
---------------------- OPTIONS -----------------------------------------
{dtM}   dtM
1000.0   WtrDpth
0.0      WtrDnsty
9.81     g
RK4      tScheme
60.0     TmaxIC
1.0e-7   threshIC
--------------------- OUTPUTS --------------------------------------------
END
------------------------- need this line --------------------------------------
"""


def moordyn_swing(t_end: float, work: Path, dtM: float = 8e-4, segments: int = 40) -> dict:
    """The swing run by MoorDyn (its Python module): the end at x = 100 m moved 5 cm sideways by
    the same ramp over 0.5 s, coupled every 0.01 s (slidebeam's dt), the middle node's y
    recorded each time. Returns the wall and CPU time of the time integration (its static
    initialisation apart), omega and the support tension after the initialisation."""
    import os
    import time

    import moordyn

    # MoorDyn reports every coupling step on the C library's stdout: kept off the table
    sys.stdout.flush()
    saved = os.dup(1)
    quiet = os.open(os.devnull, os.O_WRONLY)
    os.dup2(quiet, 1)
    try:
        return _moordyn_swing(moordyn, t_end, work, dtM, segments)
    finally:
        os.dup2(saved, 1)
        os.close(saved)
        os.close(quiet)


def _moordyn_swing(moordyn, t_end: float, work: Path, dtM: float, segments: int) -> dict:
    import time

    path = work / "moordyn_swing.txt"
    path.write_text(MOORDYN_INPUT.format(segments=segments, dtM=dtM))
    system = moordyn.Create(str(path))
    moordyn.Init(system, [100.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    line = moordyn.GetLine(system, 1)
    mid = moordyn.GetLineN(line) // 2
    # the force on the coupled end point (its segment's tension and its half-segment's weight)
    tension = math.sqrt(sum(f * f for f in moordyn.GetPointForce(moordyn.GetPoint(system, 2))))
    dt, steps = 0.01, int(round(t_end / 0.01))
    times, ys = [], []
    wall0, cpu0 = time.perf_counter(), time.process_time()
    for k in range(steps):
        t1 = (k + 1) * dt
        ramp = min(t1 / 0.5, 1.0)
        moordyn.Step(system, [100.0, 0.05 * ramp, 0.0], [0.0, 0.1 if t1 <= 0.5 + 1e-12 else 0.0, 0.0], k * dt, dt)
        times.append(t1)
        ys.append(moordyn.GetLineNodePos(line, mid)[1])
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    moordyn.Close(system)
    return {"wall": wall, "cpu": cpu, "omega": fit_frequency(times, ys), "tension": tension}


def start_tension(history: Path) -> float:
    row = next(csv.DictReader(history.open()))
    return math.sqrt(sum(float(row[f"spherical[cable@start].f{c}"]) ** 2 for c in "xyz"))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--repeat", type=int, default=3, help="runs per scene and variant (the median is shown)")
    p.add_argument("--quick", action="store_true", help="the swings over 10.5 s instead of 60.5 s")
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUE",
                   help="an override for the scenes given (as `slidebeam run --set`), e.g. contact.0.mu=0")
    p.add_argument("scenes", nargs="*", help="scene files (default: the cable scenes)")
    args = p.parse_args()
    scenes = [(s, list(args.sets)) for s in args.scenes] if args.scenes else SCENES
    print("| scene | unknowns | Newton | ms / step | iterations / step | Jacobians / step | rejected / step "
          "| assembly share | vs full Newton |")
    print("|---|---|---|---|---|---|---|---|---|")
    t_end = 10.5 if args.quick else 60.5
    swings: dict[str, Swing] = {}  # per swing scene and spans: its accuracy and the times of its own Newton variant
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for scene, sets in scenes:
            if scene in SWINGS and args.quick:
                sets = [*sets, "analysis.t_end=10.5"]
            spans = [x.split("=")[1] for x in sets if x.startswith("beam.0.spans=")]
            label = Path(scene).stem + (f" ({spans[0]} spans)" if spans else "")
            full_ms = None
            rows = []
            for name, petsc in VARIANTS:
                ms, its, jac, rej, share, stepping, wall = [], [], [], [], [], [], []
                for k in range(args.repeat):
                    out = work / f"out_{k}"
                    s = run(scene, sets, petsc, out)
                    n = max(1, s["steps"])
                    ms.append(1e3 * s["stepping_time_s"] / n)
                    its.append(s["newton_iterations"] / n)
                    jac.append(s["jacobian_evaluations"] / n)
                    rej.append(s["rejected_steps"] / n)
                    share.append(assembly_share(s))
                    stepping.append(s["stepping_time_s"])
                    wall.append(s["wall_time_s"])
                    if scene in SWINGS and label not in swings:
                        swings[label] = Swing(label, SWINGS[scene].format(spans=spans[0] if spans else 16), swing_frequency(out / "history.csv"),
                                              start_tension(out / "history.csv"))
                med = statistics.median(ms)
                if scene in SWINGS and name == OWN_VARIANT[scene]:
                    swings[label].times = (statistics.median(stepping), statistics.median(wall))
                    swings[label].variant = name
                if name == "full Newton":
                    full_ms = med
                rows.append((name, med, statistics.median(its), statistics.median(jac), statistics.median(rej),
                             statistics.median(share)))
                unknowns = s["unknowns"]
            for name, med, it, jc, rj, sh in rows:
                ratio = f"{full_ms / med:.2f}x faster" if full_ms else "–"
                label_sets = Path(scene).stem + (f" ({', '.join(sets)})" if sets else "")
                print(f"| {label_sets} | {unknowns} | {name} | {med:.3f} | {it:.2f} | {jc:.3f} | {rj:.3f} | {sh:.0%} "
                      f"| {ratio} |", flush=True)
        if swings:
            print()
            T_exact = catenary_tension()
            for sw in swings.values():
                print(f"{sw.label}: omega = {sw.omega:.7f} rad/s (exact linear {EXACT_OMEGA}: relative error "
                      f"{abs(sw.omega / EXACT_OMEGA - 1):.1e}); support tension {sw.tension:.4f} N (elastic "
                      f"catenary {T_exact:.4f} N: relative error {abs(sw.tension / T_exact - 1):.1e})")
            side_by_side(list(swings.values()), t_end, args.repeat, work)


@dataclasses.dataclass
class Swing:
    label: str
    model: str
    omega: float
    tension: float
    times: tuple[float, float] = (math.nan, math.nan)  # median stepping and wall time, s
    variant: str = ""


def side_by_side(swings: list[Swing], t_end: float, repeat: int, work: Path) -> None:
    """The swings by slidebeam and by MoorDyn in one table, where MoorDyn imports."""
    try:
        import moordyn  # noqa: F401
    except ImportError:
        print("\n(MoorDyn not importable here: the side-by-side is skipped; the docstring says how to install it)")
        return
    runs = [moordyn_swing(t_end, work) for _ in range(repeat)]
    md_wall = statistics.median(r["wall"] for r in runs)
    md_cpu = statistics.median(r["cpu"] for r in runs)
    md = runs[0]
    T_exact = catenary_tension()
    print(f"\nThe swing ({t_end - 0.5:g} s after the 0.5 s ramp), side by side (medians of {repeat}):\n")
    print("| code | model | time step | time stepping, s | whole run, s | omega error | support tension error "
          "| time stepping / MoorDyn's |")
    print("|---|---|---|---|---|---|---|---|")
    for sw in swings:
        stepping, wall = sw.times
        print(f"| slidebeam ({sw.variant}) | {sw.model} | 0.01 s | {stepping:.2f} | {wall:.2f} "
              f"| {abs(sw.omega / EXACT_OMEGA - 1):.1e} | {abs(sw.tension / T_exact - 1):.1e} "
              f"| {stepping / md_wall:.2f} |")
    print(f"| MoorDyn 2.7.2 | 40 lumped-mass segments, RK4 | 8e-4 s | {md_wall:.2f} (CPU {md_cpu:.2f}) | – "
          f"| {abs(md['omega'] / EXACT_OMEGA - 1):.1e} | {abs(md['tension'] / T_exact - 1):.1e} | 1 |")


if __name__ == "__main__":
    main()
