# SPDX-License-Identifier: MIT
"""`slidebeam study` (issue 7): the machinery on tiny grids. Errors fall with dt at the order of
the schemes, the table and the diagrams are written, bad input is refused. Never a timing."""
from __future__ import annotations

import csv
import math
import re

import pytest

pytestmark = pytest.mark.skip_in_parallel  # each test starts its own processes

PNG = b"\x89PNG\r\n\x1a\n"


def test_errors_fall_at_second_order_and_everything_is_written(run_cli, root, tmp_path):
    out = run_cli("study", str(root / "runs" / "soft_pendulum.toml"), "--set", "analysis.t_end=0.2",
                  "--vary", "analysis.dt=8e-3,4e-3,2e-3", "--vary", "analysis.integrator=energy-momentum,newmark",
                  "--reference", "analysis.dt=2.5e-4", "--reference", "analysis.integrator=energy-momentum",
                  "-j", "2", "--out", "st")
    assert out.returncode == 0, out.stderr
    assert "[  7/7] reference: dt=2.5e-4, integrator=energy-momentum" in out.stdout
    rows = list(csv.DictReader((tmp_path / "st" / "study.csv").open()))
    assert len(rows) == 6
    for integrator in ("energy-momentum", "newmark"):
        err = [float(r["error_tip"]) for r in rows if r["analysis.integrator"] == integrator]
        assert err[0] > err[1] > err[2] > 0  # dt = 8e-3, 4e-3, 2e-3
        assert math.log(err[0] / err[2], 4) > 1.6  # second order
        assert all(int(r["steps"]) > 0 and int(r["linear_solves"]) > 0 for r in rows)
    em = [r for r in rows if r["analysis.integrator"] == "energy-momentum"]
    assert max(float(r["energy_drift"]) for r in em) < 1e-9  # EM keeps energy; Newmark does not
    assert min(float(r["energy_drift"]) for r in rows if r["analysis.integrator"] == "newmark") > 1e-7
    md = (tmp_path / "st" / "study.md").read_text()
    orders = dict(re.findall(r"\| integrator=(\S+) \| ([0-9.]+) \|", md))
    assert float(orders["energy-momentum"]) > 1.7 and float(orders["newmark"]) > 1.7
    for q in ("tip", "energy"):
        assert (tmp_path / "st" / f"study_{q}.png").read_bytes()[:8] == PNG
    assert not (tmp_path / "st" / "study_s.png").exists()  # no sliding joint, no s diagram
    assert not list((tmp_path / "st" / "runs").glob("*/beams.h5"))  # studies write no XDMF


def test_default_reference_is_the_finest_run_and_study_files_work(run_cli, root, tmp_path):
    study = tmp_path / "tiny.toml"
    study.write_text(f"""
[study]
scene = "{root / 'runs' / 'seed' / 'free_fall_1+1.toml'}"
set = {{ "analysis.t_end" = 0.02 }}
vary = {{ "analysis.dt" = [2e-3, 1e-3], "beam.AB.quadrature&beam.CM.quadrature" = ["full", "reduced"] }}
""")
    out = run_cli("study", str(study), "--out", "st", "-q")
    assert out.returncode == 0, out.stderr
    rows = list(csv.DictReader((tmp_path / "st" / "study.csv").open()))
    assert len(rows) == 4
    assert all(r["beam.AB.quadrature"] == r["beam.CM.quadrature"] for r in rows)  # varied together
    ref = [r for r in rows if r["is_reference"] == "True"]
    assert len(ref) == 1 and float(ref[0]["error_tip"]) == 0.0 and ref[0]["analysis.dt"] == "0.001"
    assert "finest run of the grid" in (tmp_path / "st" / "study.md").read_text()
    assert (tmp_path / "st" / "study_s.png").read_bytes()[:8] == PNG  # a sliding joint: s is compared


def test_tolerance_driven_runs_have_curves_of_their_own(run_cli, root, tmp_path):
    """--adapt: each integrator also runs with error-controlled steps at each tolerance, in
    curves of their own whose error follows the tolerance (order ~1 along rtol)."""
    out = run_cli("study", str(root / "runs" / "soft_pendulum.toml"), "--set", "analysis.t_end=0.3",
                  "--vary", "analysis.dt=8e-3,4e-3", "--vary", "analysis.integrator=energy-momentum,newmark",
                  "--adapt", "1e-3,1e-4,1e-5", "--reference", "analysis.dt=1e-4", "-j", "2", "--out", "st")
    assert out.returncode == 0, out.stderr
    rows = list(csv.DictReader((tmp_path / "st" / "study.csv").open()))
    adaptive = [r for r in rows if r.get("analysis.adapt")]
    assert len(rows) == 10 and len(adaptive) == 6
    assert all(not r["analysis.dt"] for r in adaptive)
    for r in adaptive:
        rtol = float(r["analysis.adapt"].strip("{}").partition("=")[2])
        assert 0.1 * rtol < float(r["error_tip"]) < 10 * rtol, (r["run"], r["error_tip"])
    md = (tmp_path / "st" / "study.md").read_text()
    orders = dict(re.findall(r"\| integrator=(\S+), adaptive \| ([0-9.]+) \|", md))
    assert set(orders) == {"energy-momentum", "newmark"}
    assert all(0.8 < float(v) < 1.2 for v in orders.values()), orders


@pytest.mark.parametrize("args, words", [
    (["--vary", "analysis.dt=1e-3", "--adapt", "2"], "numbers in (0, 1)"),
    (["--vary", "analysis.dt"], "key=v1,v2"),
    ([], "nothing to vary"),
    (["--vary", "analysis.dt=1e-3", "--reference", "analysis.dt"], "key=value"),
])
def test_bad_study_input_is_a_clear_error(run_cli, root, args, words):
    out = run_cli("study", str(root / "runs" / "soft_pendulum.toml"), *args)
    assert out.returncode == 2 and words in out.stderr and "Traceback" not in out.stderr


def test_unknown_study_file_key(run_cli, tmp_path):
    study = tmp_path / "bad.toml"
    study.write_text('[study]\nscene = "x.toml"\nvary = { "analysis.dt" = [1e-3] }\nrefrence = {}\n')
    out = run_cli("study", str(study))
    assert out.returncode == 2 and "refrence" in out.stderr and "allowed" in out.stderr
