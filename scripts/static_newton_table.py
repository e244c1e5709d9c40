#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Newton iterations of the static solves: prints the markdown tables of docs/verification.md,
"Statics on the constraint manifold" (the "after" columns; about 30 s).

  - load steps of runs/rollup.toml, bend45.toml, elastica.toml and right_angle_cantilever.toml
    (static, peak load 50 at t = 1, 10 steps): Newton iterations per step (max, mean), load-step
    cuts, largest final |F| of a load step
  - start = "equilibrium" of runs/cables/hanging_rope.toml and zip_line.toml: continuation steps
    and Newton iterations
  - the slender elastica (EA/EI = 1e7, 40 load steps as in scripts/convergence_table.py) for
    every quadrature at 8 / 16 / 32 spans and P L^2/EI = 1 and 10: cuts and iterations

    scripts/static_newton_table.py            # Newton on the director manifold (the default)
    scripts/static_newton_table.py --plain    # plain Newton on the full system (-sb_condense_directors false)
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--plain", action="store_true", help="plain Newton on the full system (-sb_condense_directors false)")
    args = parser.parse_args()
    from petsc4py import PETSc

    import slidebeam

    if args.plain:
        PETSc.Options().setValue("sb_condense_directors", "false")

    def static(name: str, sets: list[str]) -> tuple[list[int], int, float, bool]:
        sim = slidebeam.Simulation(slidebeam.load_scene(ROOT / "runs" / name, sets))
        records = sim.solve_static()
        its = [r.newton_iterations for r in records[1:]]
        ok = records[-1].converged and records[-1].t == sim.scene.analysis.t_end
        return its, sim.load_step_cuts, max(r.residual_norm for r in records[1:]), ok

    print("| scene | load steps | Newton iterations per step: max / mean | cuts | largest final abs(F) |")
    print("|---|---|---|---|---|")
    for name, sets in (("rollup.toml", []), ("bend45.toml", []), ("elastica.toml", []),
                       ("right_angle_cantilever.toml", ['analysis.type="static"', "analysis.t_end=1.0", "analysis.steps=10"])):
        its, cuts, worst, ok = static(name, sets)
        print(f"| {name} | {len(its)} | {max(its)} / {sum(its) / len(its):.2f} | {cuts}{'' if ok else ' (failed)'} | "
              f"{worst:.1e} |", flush=True)

    print("\n| equilibrium start | continuation steps | Newton iterations |")
    print("|---|---|---|")
    for name in ("hanging_rope.toml", "zip_line.toml"):
        sim = slidebeam.Simulation(slidebeam.load_scene(ROOT / "runs" / "cables" / name, ["output.xdmf=false"]))
        r = sim.settle()
        print(f"| {name} | {r.pseudo_steps} | {r.newton_iterations}{'' if r.converged else ' (failed)'} |", flush=True)

    print("\n| slender elastica, EA/EI = 1e7 | P L²/EI | 8 spans | 16 spans | 32 spans |")
    print("|---|---|---|---|---|")
    for q in ("full", "reduced", "assumed_strain"):
        for P in (1.0, 10.0):
            cells = []
            for n in (8, 16, 32):
                its, cuts, _, ok = static("elastica.toml", [
                    f"beam.0.spans={n}", f"beam.0.quadrature={q}", "beam.0.section.EA=1e7", "beam.0.section.kGA=1e7",
                    f"load.0.value=[0,{P},0]", "analysis.steps=40"])
                cells.append("fails" if not ok else f"{cuts} cuts, {max(its)} / {sum(its) / len(its):.1f}")
            print(f"| {q} | {P:g} | " + " | ".join(cells) + " |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
