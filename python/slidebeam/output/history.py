# SPDX-License-Identifier: MIT
"""The history of a dynamic run as one table of numbers: what history.csv prints and what a
checkpoint keeps (as a float64 dataset, exact), built once from the records.

Columns, one row per record: the :meth:`DynamicRecord.header` columns (``reason`` a placeholder:
the reasons are a list beside the table), then per tracked point x, y, z; per reaction its force
(and moment where it has one); the effects' named values (outputs: a sliding joint's among them); per counted effect its work (dissipated energy as it is kept: negative). The layout (how many of
each, the reactions' effects) comes from the first record; every record of a run has it.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..run.dynamics import DynamicRecord, Reaction

_BASE_KINDS = "iffcsii" + "f" * 15  # step .. constraint_residual; c: converged, an integer too
_REASON = 4  # the reason's column


@dataclass(frozen=True)
class Layout:
    """What the columns after the header's hold."""

    tracked: int
    reactions: list[tuple[str, bool]]  # (effect, holds a moment)
    flows: int
    outputs: int = 0

    @staticmethod
    def of(record: DynamicRecord, flows: int) -> "Layout":
        return Layout(len(record.tracked), [(r.effect, r.moment is not None) for r in record.reactions], flows, len(record.outputs))

    def as_dict(self) -> dict[str, object]:
        return {"tracked": self.tracked, "reactions": [list(r) for r in self.reactions], "flows": self.flows, "outputs": self.outputs}

    @staticmethod
    def from_dict(d: dict) -> "Layout":
        """The layout a checkpoint keeps (an earlier version's "joints" columns are not read:
        read_checkpoint refuses its records, whose outputs lack them)."""
        return Layout(int(d["tracked"]), [(str(e), bool(m)) for e, m in d["reactions"]],
                      int(d["flows"]), int(d.get("outputs", 0)))

    @property
    def columns(self) -> int:
        return (len(_BASE_KINDS) + 3 * self.tracked + sum(6 if m else 3 for _, m in self.reactions) + self.outputs + self.flows)

    @property
    def kinds(self) -> str:
        return _BASE_KINDS.replace("c", "i") + "f" * (self.columns - len(_BASE_KINDS))

    @property
    def flow_columns(self) -> slice:
        return slice(self.columns - self.flows, self.columns)


def _row(r: DynamicRecord, flows: int) -> list[float]:
    row = [r.step, r.t, r.dt, r.converged, 0.0, r.newton_iterations, r.rejected_steps, r.residual_norm,
           r.kinetic_energy, r.strain_energy, r.potential_energy, r.total_energy, r.work, r.dissipated,
           r.energy_balance_error, *r.linear_momentum, *r.angular_momentum, r.constraint_residual]
    for p in r.tracked:
        row += p
    for x in r.reactions:
        row += x.force
        if x.moment is not None:
            row += x.moment
    row += r.outputs
    row += r.flows or [0.0] * flows
    return row


# The rows of the last table, by record: the end of a run tables its records twice (checkpoint,
# history.csv). The records are kept with their rows, so an id is never that of another record.
_last_rows: dict[int, tuple[DynamicRecord, int, list[float]]] = {}


def table(records: list[DynamicRecord], flows: int) -> tuple[np.ndarray, list[str], Layout]:
    """(values: records x columns, the reasons, the layout) of a run's records; ``flows``: how
    many effects' works are counted."""
    global _last_rows
    layout = Layout.of(records[0], flows)
    rows = {}
    for r in records:
        kept = _last_rows.get(id(r))
        rows[id(r)] = kept if kept is not None and kept[0] is r and kept[1] == flows else (r, flows, _row(r, flows))
    _last_rows = rows
    values = np.array([rows[id(r)][2] for r in records], dtype=np.float64).reshape(len(records), layout.columns)
    return values, [r.reason for r in records], layout


def records(values: np.ndarray, reasons: list[str], layout: Layout) -> list[DynamicRecord]:
    """The records of a table (the inverse of :func:`table`; their joints are left empty: the
    caller that knows whose outputs are whose fills them, Simulation.joints_of)."""
    out = []
    for row, reason in zip(values.tolist(), reasons):
        k = len(_BASE_KINDS)
        tracked = [tuple(row[k + 3 * i:k + 3 * i + 3]) for i in range(layout.tracked)]
        k += 3 * layout.tracked
        reactions = []
        for effect, has_moment in layout.reactions:
            moment = tuple(row[k + 3:k + 6]) if has_moment else None
            reactions.append(Reaction(effect, tuple(row[k:k + 3]), moment))
            k += 6 if has_moment else 3
        outputs = row[k:k + layout.outputs]
        k += layout.outputs
        out.append(DynamicRecord(
            step=int(row[0]), t=row[1], dt=row[2], converged=bool(row[3]), reason=reason,
            newton_iterations=int(row[5]), rejected_steps=int(row[6]), residual_norm=row[7],
            kinetic_energy=row[8], strain_energy=row[9], potential_energy=row[10],
            work=row[12], dissipated=row[13], energy_balance_error=row[14],
            linear_momentum=tuple(row[15:18]), angular_momentum=tuple(row[18:21]), constraint_residual=row[21],
            tracked=tracked, reactions=reactions, outputs=outputs, flows=row[k:k + layout.flows]))
    return out
