"""run_experiment: thesis experiment 5.2 on the shipped demo map."""
import csv
import subprocess
import sys
from pathlib import Path

import pytest

DEMO_MAP = Path(__file__).resolve().parents[1] / "maps" / "demo_map.npz"


def _run(*args):
    return subprocess.run([sys.executable, "-m", "hexapod_adapt.experiment_cli", *args], capture_output=True,
                          text=True, timeout=300)


@pytest.mark.slow
def test_scenario_s2_runs_in_every_orientation_and_writes_csv(tmp_path):
    out = tmp_path / "runs.csv"
    r = _run("--archive", str(DEMO_MAP), "--scenarios", "S2", "--out", str(out))
    assert r.returncode == 0, r.stderr
    rows = list(csv.DictReader(out.open()))
    assert [row["failed_legs"] for row in rows] == ["1 4", "2 5", "3 6"]
    for row in rows:
        assert 1 <= int(row["trials"]) <= 20
        # two opposite legs stop the control tripod; the map has gaits that still walk forwards
        assert float(row["best_speed"]) > float(row["control_speed"])


def test_bad_inputs_are_refused(tmp_path):
    r = _run("--archive", str(tmp_path / "missing.npz"))
    assert r.returncode == 2 and "no such archive" in r.stderr
    r = _run("--archive", str(DEMO_MAP), "--alpha", "0")
    assert r.returncode == 2 and "alpha" in r.stderr
