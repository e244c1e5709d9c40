# SPDX-License-Identifier: MIT
"""The history table and its CSV text: every float printed as Python's repr prints it (so
history.csv reads back bit for bit), integers and text columns as the csv module writes them."""
from __future__ import annotations

import csv
import io

import numpy as np


def test_the_core_prints_floats_as_python_repr_does():
    from slidebeam import _core

    rng = np.random.default_rng(7)
    values = list(rng.standard_normal(5000) * 10.0 ** rng.integers(-320, 300, 5000))
    values += list(np.frombuffer(rng.bytes(8 * 5000), dtype=np.float64))  # every bit pattern: subnormals, nan
    values += [0.0, -0.0, 1.0, 0.1, 1e-4, 1e-5, 1e15, 1e16, 9.999999999999999e15, 123456789012.0, 2.0 ** 60,
               5e-324, 1.7976931348623157e308, float("inf"), -float("inf"), float("nan")]
    wrong = [v for v in values if _core.python_repr(float(v)) != repr(float(v))]
    assert not wrong, wrong[:5]


def test_csv_rows_are_what_the_csv_module_writes():
    from slidebeam import _core

    values = np.array([[3.0, 0.1, 0.0, -2.5e-7], [12.0, 1e20, 0.0, float("nan")]])
    text = ["plain", 'with, a comma and "quotes"']
    rows = [[3, repr(0.1), "plain", repr(-2.5e-7)], [12, repr(1e20), text[1], "nan"]]
    want = io.StringIO()
    csv.writer(want).writerows(rows)
    assert _core.csv_rows(values, "ifsf", text) == want.getvalue()
    assert list(csv.reader(io.StringIO(_core.csv_rows(values, "ifsf", text))))[1][2] == text[1]
