# SPDX-License-Identifier: MIT
"""Results on disk (rank 0 writes): summary.json, history.csv, final_configuration.csv.
Files are written whole or not at all (temporary file + rename)."""
from __future__ import annotations

import csv
import io
import json
import os
from pathlib import Path
from typing import Any

from .dynamics import DynamicRecord, JointState
from .simulation import Simulation, StepRecord


def _atomic_write(path: Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def prepare_output_dir(out: Path) -> None:
    """Create the output folder and prove it is writable before any work starts."""
    try:
        out.mkdir(parents=True, exist_ok=True)
        probe = out / ".write_test"
        probe.write_text("ok")
        probe.unlink()
    except OSError as err:
        raise OSError(f"output folder {out} is not writable: {err.strerror or err}") from err


def history_csv(sim: Simulation, records: list[StepRecord] | list[DynamicRecord]) -> str:
    """One row per recorded step; then tracked points as <beam>@<s>.x/.y/.z, sliding joints as
    <slider>_on_<carrier>.s/.ds_dt/.reaction.x/y/z/.gap, and the reactions of supports and rigid
    joints as <effect>.fx/fy/fz (and .mx/my/mz where they hold a moment)."""
    buf = io.StringIO()
    w = csv.writer(buf)
    track_cols = []
    for tp in sim.scene.output.track:
        name = f"{sim.scene.beams[tp.beam].name}@{tp.at:g}"
        track_cols += [f"{name}.x", f"{name}.y", f"{name}.z"]
    joint_cols = [f"{name}.{q}" for name in joint_names(sim)
                  for q in ("s", "ds_dt", "reaction.x", "reaction.y", "reaction.z", "gap")]
    first = records[0].reactions
    reaction_cols = [f"{r.effect}.{c}" for r in first
                     for c in ("fx", "fy", "fz", *(("mx", "my", "mz") if r.moment is not None else ()))]

    def tail(r: StepRecord | DynamicRecord) -> list[str]:
        return [*[repr(v) for p in r.tracked for v in p],
                *[repr(v) for j in r.joints for v in (j.s, j.ds_dt, *j.reaction, j.gap)],
                *[repr(v) for x in r.reactions for v in (*x.force, *(x.moment or ()))]]

    if sim.integrator is not None:
        flow_cols = sim.energy_flow_labels()
        roles = [role for _, role, _ in sim.integrator.energy_flows]
        w.writerow([*DynamicRecord.header(), *track_cols, *joint_cols, *reaction_cols, *flow_cols])
        for d in records:
            assert isinstance(d, DynamicRecord)
            flows = d.flows or [0.0] * len(flow_cols)
            w.writerow([*d.row(), *tail(d), *[repr(-v if role == "dissipative" else v)
                                                for v, role in zip(flows, roles)]])
        return buf.getvalue()
    w.writerow(["step", "t", "converged", "reason", "newton_iterations", "residual_norm",
                "strain_energy", "potential_energy", *track_cols, *joint_cols, *reaction_cols])
    for r in records:
        w.writerow([r.step, repr(r.t), int(r.converged), r.reason, r.newton_iterations, repr(r.residual_norm),
                    repr(r.strain_energy), repr(r.potential_energy), *tail(r)])
    return buf.getvalue()


def joint_names(sim: Simulation) -> list[str]:
    """Column prefix of each sliding joint: <slider>_on_<carrier>, numbered when repeated."""
    names = [f"{sim.scene.beams[j.slider].name}_on_{sim.scene.beams[j.carrier].name}" for j in sim.scene.sliding_joints]
    return [n if names.count(n) == 1 else f"{n}_{i + 1}" for i, n in enumerate(names)]


def sliding_joint_summary(sim: Simulation, joints: list[JointState]) -> dict[str, dict[str, object]]:
    """summary.json's `sliding_joints`: the final s, ds/dt (statics: 0), reaction and gap per joint."""
    return {name: {"final_s": j.s, "final_ds_dt": j.ds_dt, "final_reaction": list(j.reaction), "final_gap": j.gap}
            for name, j in zip(joint_names(sim), joints)}


def configuration_csv(sim: Simulation) -> str:
    """The final state sampled along every beam (output.samples_per_span points per span): centre
    line, directors, strains (minus the reference's), the spatial force and moment resultants
    and the tension, as the element has them."""
    buf = io.StringIO()
    w = csv.writer(buf)
    strain_cols = ["eps_axial", "eps_shear2", "eps_shear3", "kappa_torsion", "kappa2", "kappa3"]
    w.writerow(["beam", "s", "x", "y", "z", "d1x", "d1y", "d1z", "d2x", "d2y", "d2z", "d3x", "d3y", "d3z",
                *strain_cols, "fx", "fy", "fz", "mx", "my", "mz", "tension"])
    for b in sim.scene.beams:
        f = sim.sample_beam(b.index)
        for i, si in enumerate(f["s"]):
            row = [*f["position"][i], *f["d1"][i], *f["d2"][i], *f["d3"][i], *f["strain"][i], *f["force"][i],
                   *f["moment"][i], f["tension"][i]]
            w.writerow([b.name, repr(float(si)), *[repr(float(v)) for v in row]])
    return buf.getvalue()


def end_positions(sim: Simulation) -> dict[str, dict[str, list[float]]]:
    out = {}
    for b in sim.scene.beams:
        q = sim.evaluate(b.index, [0.0, b.geometry.length])
        out[b.name] = {"start": q[0, :3].tolist(), "end": q[1, :3].tolist()}
    return out


def write_results(sim: Simulation, out: Path, records: list[StepRecord] | list[DynamicRecord], summary: dict[str, Any],
                  rank: int) -> None:
    """Collective (evaluation gathers), rank 0 writes. The summary is written last, so a
    summary marked complete is never beside partial files."""
    history = history_csv(sim, records)
    config = configuration_csv(sim)
    summary = {**summary, "final_end_positions": end_positions(sim)}
    if rank != 0:
        return
    _atomic_write(out / "history.csv", history)
    _atomic_write(out / "final_configuration.csv", config)
    _atomic_write(out / "summary.json", json.dumps(summary, indent=2) + "\n")
