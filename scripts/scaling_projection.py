#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Project the time of a Newton iteration of a large cable net on 8 to 1024 ranks under exact
substructuring (issue 20, point 3): each rank factors its interior (as the serial code does
today, in the model's elimination order), the separator Schur complement is gathered and
factored redundantly on every rank, then each rank back-substitutes. A model on paper, fed
with this machine's measured serial cost per unknown; prints a Markdown table and writes a plot.

    scripts/scaling_projection.py                       # table + docs/scaling_projection.png
    scripts/scaling_projection.py --plot out.png --latency 2e-6 --bandwidth 12e9

The model (docs/performance.md, "Beyond this machine"):
  - a square cable net of K x K cables (K in each direction), each of n spans of director beam,
    joined where they cross; N = 2 K (n + 2) 18 unknowns (the joints' few multipliers ignored);
  - P square patches (a graph partitioner's result on such a net); a patch's boundary is crossed
    by 4 K / sqrt(P) cables, each cut a separator of 2 control points, 12 unknowns after the
    null-space condensation (6 per control point): s_r = 48 K / sqrt(P) separator unknowns
    touch a rank, S = 24 K sqrt(P) in all;
  - interior work per iteration a N / P (assembly, factorisation and solve: the measured serial
    cost per unknown per Newton iteration, which grows linearly with N);
  - the rank's Schur block comes out of its factorisation with the separators ordered last;
    forming it costs s_r^2 x the band (a few flops per entry: negligible next to the interior);
  - gathering the Schur blocks: an allgather of P s_r^2 / 4 doubles (each rank's block, sparse
    between its four sides), log2(P) latencies;
  - factoring S redundantly: its graph is the P-node patch grid with blocks of s_r / 4
    unknowns per patch edge; nested dissection of a sqrt(P) x sqrt(P) grid costs about
    (sqrt(P) b)^3 flops at its top separator (b = s_r / 2 unknowns per patch across it), summed
    over levels about 1.5 times that; dense-LU speed `flops` (a core's LAPACK rate);
  - solving with S and back-substituting: negligible next to the factorisation (Jacobian reused
    over a step's iterations would remove the factorisation from all but the first iteration).
  - strategy "as built": what the coupling correction does today instead of taking the rank's
    Schur block from its factorisation: one reduced block solve per interface unknown of the
    rank at every Jacobian, each costing the whole block (SOLVE_US_PER_UNKNOWN, measured), S
    factored redundantly.
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# Measured on this machine (scripts/bench_scaling.py, one rank, 10^3..10^5 unknowns): 2.7-3.7 us
# per step per unknown (2.8-2.9 from 1.4e4 unknowns on) at 3 Newton iterations per step.
SERIAL_US_PER_UNKNOWN_ITERATION = 3.0 / 3
# Measured (the 20 x 20 net of make_cables.py --net 20 --spans 4 on 2 ranks, -log_view): a reduced
# block solve of a 48 960-unknown block took 0.73 ms, 0.015 us per unknown of the block.
SOLVE_US_PER_UNKNOWN = 0.73e3 / 48960
CONDENSED_PER_CUT = 12  # 2 control points x 6 condensed unknowns
UNKNOWNS_PER_SPAN = 18


def net(unknowns: float) -> tuple[int, int]:
    """(K, n): a square net of K x K cables of n spans with about `unknowns` unknowns, the cables
    about 10 times longer (in spans) than there are cables across."""
    k = max(2, round((unknowns / (2 * UNKNOWNS_PER_SPAN * 10)) ** 0.5))
    n = max(4, round(unknowns / (2 * k * UNKNOWNS_PER_SPAN) - 2))
    return k, n


def dense_lu_flops(n: float) -> float:
    return 2.0 / 3.0 * n**3


def iteration_time(layout: str, unknowns: float, ranks: int, strategy: str, latency: float, bandwidth: float,
                   flops: float, carriers: int = 10) -> dict[str, float]:
    """Seconds per Newton iteration: interior, gather of the Schur blocks, Schur factorisation.

    layout "bundle": `carriers` parallel cables joined by hangers (a ropeway, a bridge's cable
    bundle; scripts/make_cables.py), cut across on P - 1 planes: separators of 12 `carriers`
    unknowns, S block-tridiagonal (P - 1 blocks), factored in P (12 c)^3 flops.
    layout "net": the K x K net above, P square patches; S's factorisation is dominated by
    the top separator of nested dissection, about 24 K unknowns across the whole net (a dense
    block of (24 K)^3 flops, which a serial direct solve of the net pays too).
    strategy "redundant": every rank factors S; "distributed": S factored by
    min(P, 64) ranks at half a core's dense-LU rate each, plus log2 P latencies per level;
    "as built": redundant, plus a block solve per interface unknown of the rank (s_rank / 2).
    """
    a = SERIAL_US_PER_UNKNOWN_ITERATION * 1e-6
    if layout == "bundle":
        s_rank = 2 * CONDENSED_PER_CUT * carriers          # two cut planes per rank
        schur_unknowns = (ranks - 1) * CONDENSED_PER_CUT * carriers
        schur_flops = max(ranks - 1, 0) * dense_lu_flops(CONDENSED_PER_CUT * carriers) * 4  # tridiagonal blocks
        serial_extra = 0.0
    else:
        k, _ = net(unknowns)
        root = math.sqrt(ranks)
        s_rank = 48 * k / root
        schur_unknowns = 24 * k * root if ranks > 1 else 0.0
        schur_flops = 1.5 * dense_lu_flops(24 * k)
        serial_extra = schur_flops / flops                  # the serial solve's own top separator
    interior = a * unknowns / ranks
    if ranks == 1:
        total = interior + serial_extra
        return {"interior": interior, "gather": 0.0, "schur": serial_extra, "total": total, "S": 0.0}
    gather = math.log2(ranks) * latency + 8 * ranks * s_rank**2 / 4 / bandwidth
    if strategy in ("redundant", "as built"):
        schur = schur_flops / flops
        if strategy == "as built":
            schur += s_rank / 2 * SOLVE_US_PER_UNKNOWN * 1e-6 * unknowns / ranks
    else:
        q = min(ranks, 64)
        schur = schur_flops / (0.5 * q * flops) + math.log2(ranks) * 10 * latency
    total = interior + gather + schur
    return {"interior": interior, "gather": gather, "schur": schur, "total": total, "S": schur_unknowns}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--latency", type=float, default=1.5e-6, help="network latency, s (InfiniBand HDR: about 1.5e-6)")
    ap.add_argument("--bandwidth", type=float, default=12e9, help="bytes/s per link (HDR 100: about 12e9)")
    ap.add_argument("--flops", type=float, default=2e10, help="dense LU rate of one core, flop/s")
    ap.add_argument("--plot", default=str(ROOT / "docs" / "scaling_projection.png"), help="plot file ('' for none)")
    args = ap.parse_args()

    ranks = [1, 2, 8, 16, 32, 64, 128, 256, 512, 1024]
    cases = [("bundle", 1e6), ("bundle", 1e7), ("net", 1e6), ("net", 1e7)]
    print(f"latency {args.latency:g} s, bandwidth {args.bandwidth:g} B/s, dense LU {args.flops:g} flop/s, "
          f"interior {SERIAL_US_PER_UNKNOWN_ITERATION:g} us per unknown per Newton iteration (measured)\n")
    print("| layout, unknowns | strategy | ranks | separator unknowns S | interior, ms | gather, ms | "
          "Schur factorisation, ms | per iteration, ms | speed-up | efficiency |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    curves = {}
    limits = []
    for layout, n in cases:
        for strategy in ("as built", "redundant", "distributed"):
            base = iteration_time(layout, n, 1, strategy, args.latency, args.bandwidth, args.flops)["total"]
            curve = []
            for p in ranks:
                t = iteration_time(layout, n, p, strategy, args.latency, args.bandwidth, args.flops)
                speedup = base / t["total"]
                curve.append(speedup)
                if p in (1, 8, 64, 1024):
                    print(f"| {layout}, {n:.0e} | {strategy} | {p} | {t['S']:.0f} | {1e3 * t['interior']:.3g} | "
                          f"{1e3 * t['gather']:.3g} | {1e3 * t['schur']:.3g} | {1e3 * t['total']:.3g} | "
                          f"{speedup:.3g} | {100 * speedup / p:.0f} % |")
            curves[(layout, n, strategy)] = curve
            stop = next((p for p, sp in zip(ranks, curve) if p > 1 and sp / p < 0.5), None)
            limits.append(f"{layout} {n:.0e}, {strategy}: efficiency below 50 % from "
                          f"{stop if stop else 'beyond 1024'} ranks")
    print()
    for line in limits:
        print(f"- {line}")
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6, 4))
        ax.loglog(ranks, ranks, "k:", label="ideal")
        for (layout, n, strategy), sp in curves.items():
            ax.loglog(ranks, sp, {"distributed": "o-", "redundant": "s--", "as built": "x:"}[strategy], ms=3,
                      label=f"{layout} {n:.0e}, {strategy}")
        ax.set_xlabel("ranks")
        ax.set_ylabel("speed-up per Newton iteration")
        ax.set_title("Exact substructuring (model)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print(f"\nplot: {args.plot}")


if __name__ == "__main__":
    main()
