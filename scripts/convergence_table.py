#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Locking and accuracy of the director beam's quadratures (full, reduced, assumed_strain):
prints the markdown tables of docs/verification.md, "Locking: convergence tables".

  - cantilever elastica (runs/elastica.toml), L = 1, EI = 1, EA = kGA = 1e7 and 1e9: largest tip
    error over P L^2 / EI = 1 and 10 against the extensible, shearable beam's exact tip (the
    inextensible elastica's raised by P L / EA), 8 / 16 / 32 / 64 spans, and the observed order
    from 32 to 64
  - roll-up (runs/rollup.toml, lambda = 0.25): tip error against the circle
  - 45-degree bend (runs/bend45.toml): distance from the 256-span tip of the same quadrature
  - hanging rope (runs/cables/hanging_rope.toml) against Irvine's elastic catenary

    scripts/convergence_table.py            # about 15 s
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))
sys.path.insert(0, str(ROOT / "tests" / "python"))

QUADRATURES = ("full", "reduced", "assumed_strain")
SPANS = (8, 16, 32, 64)


def fmt(x: float) -> str:
    return f"{x:.1e}" if math.isfinite(x) else "fails"  # the static solve did not converge


def order(a: float, b: float) -> str:
    return f"{math.log2(a / b):.1f}" if a > 0 and b > 0 and math.isfinite(a / b) else "-"


def main() -> int:
    argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    import numpy as np

    import slidebeam
    from slidebeam.scene.catenary import ElasticCatenary
    from test_locking_free import reissner_tip

    def elastica(n: int, load: float, EA: float, q: str) -> float:
        scene = slidebeam.load_scene(ROOT / "runs" / "elastica.toml", [
            f"beam.0.spans={n}", f"beam.0.quadrature={q}", f"beam.0.section.EA={EA}", f"beam.0.section.kGA={EA}",
            f"load.0.value=[0,{load},0]", "analysis.steps=40"])
        rec = slidebeam.Simulation(scene).solve_static()[-1]
        if not rec.converged:
            return float("nan")
        return float(np.linalg.norm(np.array(rec.tracked[0][:2]) - reissner_tip(load, EA)))

    print("### Cantilever elastica: largest tip error over P L^2/EI = 1 and 10\n")
    print("| quadrature | EA/EI | " + " | ".join(f"{n} spans" for n in SPANS) + " | order 32-64 |")
    print("|---|---|" + "---|" * len(SPANS) + "---|")
    for q in QUADRATURES:
        for EA in (1e7, 1e9):
            e = [max(elastica(n, P, EA, q) for P in (1.0, 10.0)) for n in SPANS]
            print(f"| {q} | {EA:.0e} | " + " | ".join(fmt(x) for x in e) + f" | {order(e[-2], e[-1])} |", flush=True)

    print("\n### Roll-up, lambda = 0.25: tip error against the circle\n")
    print("| quadrature | " + " | ".join(f"{n} spans" for n in SPANS) + " | order 32-64 |")
    print("|---|" + "---|" * len(SPANS) + "---|")
    L, EI, lam = 10.0, 100.0, 0.25
    th = 2 * math.pi * lam
    circle = np.array([L / th * math.sin(th), L / th * (1 - math.cos(th)), 0.0])
    for q in QUADRATURES:
        e = []
        for n in SPANS:
            scene = slidebeam.load_scene(ROOT / "runs" / "rollup.toml", [
                f"beam.0.spans={n}", f"beam.0.quadrature={q}", f"load.0.value=[0,0,{lam * 2 * math.pi * EI / L!r}]",
                "analysis.steps=10"])
            rec = slidebeam.Simulation(scene).solve_static()[-1]
            e.append(float(np.linalg.norm(np.array(rec.tracked[0]) - circle)))
        print(f"| {q} | " + " | ".join(fmt(x) for x in e) + f" | {order(e[-2], e[-1])} |", flush=True)

    print("\n### 45-degree bend, P = 600: distance from the same quadrature's 256-span tip\n")
    print("| quadrature | 256-span tip | " + " | ".join(f"{n} spans" for n in SPANS) + " | order 32-64 |")
    print("|---|---|" + "---|" * len(SPANS) + "---|")
    for q in QUADRATURES:
        tips = {}
        for n in (*SPANS, 256):
            scene = slidebeam.load_scene(ROOT / "runs" / "bend45.toml", [f"beam.0.spans={n}", f"beam.0.quadrature={q}"])
            tips[n] = np.array(slidebeam.Simulation(scene).solve_static()[-1].tracked[0])
        e = [float(np.linalg.norm(tips[n] - tips[256])) for n in SPANS]
        ref = ", ".join(f"{v:.2f}" for v in tips[256])
        print(f"| {q} | ({ref}) | " + " | ".join(fmt(x) for x in e) + f" | {order(e[-2], e[-1])} |", flush=True)

    print("\n### Hanging rope against Irvine's elastic catenary (32 spans)\n")
    r, E, rho, g = 0.006, 1e11, 7850.0, 9.81
    area = math.pi * r * r
    cat = ElasticCatenary(20.0, 2 * 26 * math.asin(10 / 26), E * area, rho * area * g)
    print(f"Catenary: H = {cat.H:.2f} N, support tension {float(cat.tension(0.0)):.2f} N, sag {cat.sag:.4f} m.\n")
    print("| quadrature | sag error | support tension error | max tension error / T_support | max shear / tension (1 m from the supports) |")
    print("|---|---|---|---|---|")
    for q in QUADRATURES:
        scene = slidebeam.load_scene(ROOT / "runs" / "cables" / "hanging_rope.toml", [f"beam.0.quadrature={q}"])
        sim = slidebeam.Simulation(scene)
        sim.run_dynamic()
        f = sim.sample_beam("rope", samples_per_span=4)
        s, T, force, pos = f["s"], f["tension"], f["force"], f["position"]
        Tc = cat.tension(s)
        tangent = np.gradient(pos, axis=0)
        tangent /= np.linalg.norm(tangent, axis=1)[:, None]
        shear = np.linalg.norm(force - np.sum(force * tangent, axis=1)[:, None] * tangent, axis=1)
        away = (s > 1.0) & (s < s[-1] - 1.0)
        sag = -pos[len(s) // 2, 2]
        print(f"| {q} | {abs(sag / cat.sag - 1):.1e} | {abs(T[0] / Tc[0] - 1):.1e} | "
              f"{np.abs(T - Tc).max() / Tc[0]:.1e} | {(shear / T)[away].max():.1e} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
