"""``run_experiment``: the thesis's simulated adaptation experiment (5.2) on one map.

    ros2 run hexapod_adapt run_experiment --archive map.npz [--scenarios S1 S3] [--out runs.csv]

For every orientation of each failure scenario: one M-BOA run with simulated trials (leg
failures as in table 5.1, collisions not fatal), next to the control tripod gait with the same
damage. Prints a row per run and a summary per scenario; ``--out`` writes the rows as CSV
(atomically).
"""
from __future__ import annotations

import argparse
import csv
import io
import sys
from dataclasses import asdict
from pathlib import Path

import numpy as np

from hexapod_adapt.adaptation import ExperimentRow, run_experiment
from hexapod_adapt.archive import ArchiveError, atomic_write_bytes, load_archive
from hexapod_adapt.mboa import MboaConfig


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="run_experiment", description=__doc__.split("\n\n")[0])
    ap.add_argument("--archive", type=Path, required=True)
    ap.add_argument("--scenarios", nargs="+", default=["S1", "S2", "S3", "S4"], choices=["S1", "S2", "S3", "S4"])
    ap.add_argument("--max-trials", type=int, default=20)
    ap.add_argument("--alpha", type=float, default=0.9)
    ap.add_argument("--kappa", type=float, default=0.05)
    ap.add_argument("--length-scale", type=float, default=0.4)
    ap.add_argument("--noise", type=float, default=0.001)
    ap.add_argument("--out", type=Path, help="CSV file of the runs")
    args = ap.parse_args(argv)
    try:
        archive = load_archive(args.archive)
        config = MboaConfig(max_trials=args.max_trials, alpha=args.alpha, kappa=args.kappa,
                            length_scale=args.length_scale, noise=args.noise)
    except (ArchiveError, ValueError) as exc:
        print(f"run_experiment: {exc}", file=sys.stderr)
        return 2

    def show(r: ExperimentRow) -> None:
        print(f"{r.scenario} legs {','.join(map(str, r.failed_legs)):4s} {r.trials:3d} trials  "
              f"adapted {r.best_speed:+.3f} m/s  control {r.control_speed:+.3f} m/s", flush=True)

    rows = run_experiment(archive, args.scenarios, config, on_row=show)
    print("\nscenario  runs  trials (mean/max)  adapted m/s  control m/s")
    for name in args.scenarios:
        sel = [r for r in rows if r.scenario == name]
        print(f"{name:8s}  {len(sel):4d}  {np.mean([r.trials for r in sel]):6.2f} / {max(r.trials for r in sel):3d}"
              f"      {np.mean([r.best_speed for r in sel]):+.3f}       {np.mean([r.control_speed for r in sel]):+.3f}")
    if args.out:
        buf = io.StringIO()
        writer = csv.DictWriter(buf, fieldnames=list(asdict(rows[0])))
        writer.writeheader()
        for r in rows:
            d = asdict(r)
            d["failed_legs"] = " ".join(map(str, r.failed_legs))
            writer.writerow(d)
        atomic_write_bytes(args.out, buf.getvalue().encode())
        print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
