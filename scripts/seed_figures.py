#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The seed paper's figures 4, 5 and 6 from the S2 scenes in runs/seed/ (issue 4).

  fig4_trajectory.png  tip-mass M trajectory (Y-Z plane) per mesh 1+1 ... 1+8: the director beam
                       with full and reduced quadrature and both beams as ANCF cables
                       (formulation = "ancf", spans = elements), energy-momentum; every panel
                       also shows the reference (ANCF 8+64, dashed)
  fig5_sliding.png     s(t) of the slider C on the 1+1 mesh, all four integrators
  fig6_energy.png      total energy H(t) - H(0) for energy-momentum, midpoint, Newmark and HHT at
                       dt = 1e-3 on 1+1 and 1+4, plus energy-momentum with the seed's
                       midpoint-evaluated joint derivative
  seed_runs.md         one row per run: energy drift max|H - H(0)| / max T, final s, largest
                       distance of M from the reference, unknowns, Newton iterations, wall time,
                       how the run ended

    scripts/seed_figures.py                  # writes docs/seed/, about a minute
    scripts/seed_figures.py --t-end 2 --out /tmp/seed
"""
from __future__ import annotations

import argparse
import sys
import time
import tomllib
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))

MESHES = ("1+1", "1+2", "1+4", "1+8")
INTEGRATORS = ("energy-momentum", "midpoint", "newmark", "hht")
# beam models, the second entry of a run's key: the director beam with full or reduced quadrature
# (the seed's scenes), or both beams as ANCF cables
MODELS = {"full": "director, full quadrature", "reduced": "director, reduced quadrature", "ancf": "ANCF cable"}
REFERENCE = ("8+64", "ancf", "energy-momentum", "exact")  # converged to 2.5e-4 m in M (against 4+32)


@dataclass
class Run:
    label: str
    mesh: str
    quadrature: str
    integrator: str
    joint_form: str
    t: list[float]
    tip: list[tuple[float, float, float]]
    unknowns: int
    s: list[float]
    H: list[float]
    kinetic_max: float
    newton: int
    wall: float
    ended: str

    def distance(self, ref: "Run") -> float:
        """Largest distance of M from its position in the reference run at the same time."""
        n = min(len(self.tip), len(ref.tip))
        return max(sum((a - b) ** 2 for a, b in zip(p, q)) ** 0.5 for p, q in zip(self.tip[:n], ref.tip[:n]))

    @property
    def drift(self) -> float:
        return max(abs(h - self.H[0]) for h in self.H) / self.kinetic_max if self.kinetic_max > 0 else 0.0


def cable_scene(mesh: str, integrator: str, t_end: float, joint_form: str):
    """The S2 scene (mesh CM+AB spans) with both beams as ANCF cables: same geometry, square
    section, supports, joint and mass; spans become elements."""
    from slidebeam import scene_from_dict

    path = ROOT / "runs" / "seed" / "free_fall_1+4.toml"
    with open(path, "rb") as f:
        data = tomllib.load(f)
    spans = dict(zip(("CM", "AB"), (int(n) for n in mesh.split("+"))))
    for beam in data["beam"]:
        beam.update(formulation="ancf", spans=spans[beam["name"]])
        for key in ("d2", "quadrature"):
            beam.pop(key, None)
        beam["section"] = {k: v for k, v in beam["section"].items() if k != "nu"}  # no shear in a cable
    data["scene"]["name"] = f"free_fall_{mesh}_ancf"
    data["analysis"].update(integrator=integrator, t_end=t_end)
    data["sliding_joint"][0]["discrete_gradient"] = joint_form
    return scene_from_dict(data, file=f"{path.name} (ANCF, mesh {mesh})", base_dir=str(path.parent))


def simulate(mesh: str, quadrature: str, integrator: str, t_end: float, joint_form: str = "exact") -> Run:
    from slidebeam import Simulation, load_scene

    if quadrature == "ancf":
        scene = cable_scene(mesh, integrator, t_end, joint_form)
    else:
        suffix = "_reduced" if quadrature == "reduced" else ""
        path = ROOT / "runs" / "seed" / f"free_fall_{mesh}{suffix}.toml"
        sets = [f"analysis.integrator={integrator}", f"analysis.t_end={t_end}",
                f"sliding_joint.0.discrete_gradient={joint_form}"]
        if not path.exists():  # a mesh without its own scene (the 4+32 comparison): spans set
            path = path.with_name(f"free_fall_1+4{suffix}.toml")
            sets += [f"beam.{b}.spans={n}" for b, n in zip(("CM", "AB"), mesh.split("+"))]
        scene = load_scene(path, sets)
    sim = Simulation(scene)
    t0 = time.perf_counter()
    out = sim.run_dynamic()
    wall = time.perf_counter() - t0
    recs = [r for r in out.records if r.converged]
    ended = "completed" if out.complete else (f"stopped at t = {recs[-1].t:.3f} s (slider at carrier end)"
                                              if not out.failed else f"Newton failed at t = {recs[-1].t:.3f} s")
    label = f"{mesh} {quadrature}, {integrator}" + (" (seed's joint derivative)" if joint_form == "midpoint" else "")
    return Run(label, mesh, quadrature, integrator, joint_form, [r.t for r in recs], [r.tracked[0] for r in recs],
               sim.x.getSize(),
               [r.joints[0].s for r in recs], [r.total_energy for r in recs],
               max(r.kinetic_energy for r in recs), out.newton_iterations, wall, ended)


def figures(runs: dict[tuple[str, str, str, str], Run], out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    # Fig. 4: trajectory of M in the swing plane, per mesh, quadrature and formulation
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8), sharey=True)
    ref = runs[REFERENCE]
    for ax, model in zip(axes, ("full", "reduced", "ancf")):
        for mesh in MESHES:
            r = runs[(mesh, model, "energy-momentum", "exact")]
            ax.plot([p[2] for p in r.tip], [p[1] for p in r.tip], label=f"{mesh}: {r.distance(ref):.1e} m")
        ax.plot([p[2] for p in ref.tip], [p[1] for p in ref.tip], "k--", lw=0.8, label=f"reference ({REFERENCE[0]} ANCF)")
        ax.set_title(f"tip mass M, {MODELS[model]}" if model == "ancf" else f"tip mass M, {model} quadrature")
        ax.set_xlabel("Z [m]")
        ax.grid(alpha=0.3)
        ax.legend(title="mesh CM+AB: max |M - M_ref|", fontsize=8)
    axes[0].set_ylabel("Y [m]")
    fig.tight_layout()
    fig.savefig(out / "fig4_trajectory.png", dpi=120)
    plt.close(fig)

    # Fig. 5: sliding coordinate on 1+1
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for integ in INTEGRATORS:
        r = runs[("1+1", "full", integ, "exact")]
        ax.plot(r.t, r.s, label=integ)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("s of C on AB [m]")
    ax.set_title("sliding coordinate, mesh 1+1")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "fig5_sliding.png", dpi=120)
    plt.close(fig)

    # Fig. 6: total energy on 1+1 and 1+4
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, mesh in zip(axes, ("1+1", "1+4")):
        keys = [(mesh, "full", i, "exact") for i in INTEGRATORS] + [(mesh, "full", "energy-momentum", "midpoint")]
        for key in keys:
            r = runs[key]
            name = key[2] + (" (seed's joint derivative)" if key[3] == "midpoint" else "")
            ax.plot(r.t, [h - r.H[0] for h in r.H], label=f"{name}: {r.ended.split(' (')[0]}")
        ax.set_title(f"total energy H(t) - H(0), mesh {mesh}, dt = 1e-3")
        ax.set_xlabel("t [s]")
        ax.set_ylabel("[J]")
        ax.set_yscale("symlog", linthresh=1e-10)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "fig6_energy.png", dpi=120)
    plt.close(fig)


def table(runs: dict[tuple[str, str, str, str], Run]) -> str:
    ref = runs[REFERENCE]
    lines = ["| mesh | beam model | integrator | joint derivative | energy drift max\\|H-H0\\|/max T | final s [m] "
             f"| max \\|M - M_ref\\| [m] (ref: {REFERENCE[0]} ANCF) | unknowns | Newton iterations | wall time [s] | run |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in runs.values():
        lines.append(f"| {r.mesh} | {MODELS[r.quadrature]} | {r.integrator} | {'exact' if r.joint_form == 'exact' else 'seed (midpoint)'} "
                     f"| {r.drift:.2e} | {r.s[-1]:.5f} | {r.distance(ref):.2e} | {r.unknowns} | {r.newton} | {r.wall:.2f} | {r.ended} |")
    return "\n".join(lines) + "\n"


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--t-end", type=float, default=1.0, help="simulated time per run [s] (default 1)")
    p.add_argument("--out", type=Path, default=ROOT / "docs" / "seed", help="output folder (default docs/seed)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress lines")
    args = p.parse_args()

    import petsc4py

    petsc4py.init([sys.argv[0]])
    args.out.mkdir(parents=True, exist_ok=True)
    plan = [(m, q, "energy-momentum", "exact") for q in ("full", "reduced", "ancf") for m in MESHES]
    plan += [("4+32", "full", "energy-momentum", "exact"), ("4+32", "ancf", "energy-momentum", "exact"), REFERENCE]
    plan += [(m, "full", i, "exact") for m in ("1+1", "1+4") for i in INTEGRATORS[1:]]
    plan += [(m, "full", "energy-momentum", "midpoint") for m in ("1+1", "1+4")]
    runs: dict[tuple[str, str, str, str], Run] = {}
    for n, key in enumerate(plan, 1):
        r = simulate(*key[:3], t_end=args.t_end, joint_form=key[3])
        runs[key] = r
        if not args.quiet:
            print(f"[{n:2d}/{len(plan)}] {r.label:55s} drift {r.drift:.2e}  s = {r.s[-1]:.4f}  "
                  f"{r.wall:5.2f} s  {r.ended}", flush=True)
    figures(runs, args.out)
    (args.out / "seed_runs.md").write_text(table(runs))
    print(f"wrote {args.out}/fig4_trajectory.png, fig5_sliding.png, fig6_energy.png, seed_runs.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
