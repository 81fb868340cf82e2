"""``ros2 run hexapod_sim fidelity_table``: the fidelity table (markdown) for one or both
engines, and with ``--agreement-map`` how well the engines agree over a map's gaits.

    fidelity_table                                   # both engines side by side
    fidelity_table --engine mujoco
    fidelity_table --agreement-map hexapod_adapt/maps/demo_map.npz
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from hexapod_sim.fidelity import agreement, fidelity_rows, markdown
from hexapod_sim.simulator import ENGINES, SimConfig, create_simulator


def map_genotypes(path: Path) -> np.ndarray:
    """The genotypes of the filled niches of an archive file (.npz written by generate_map)."""
    try:
        with np.load(path, allow_pickle=False) as data:
            fitness, genotypes = np.asarray(data["fitness"], dtype=float), np.asarray(data["genotypes"], dtype=float)
    except (OSError, KeyError, ValueError) as exc:
        raise ValueError(f"{path}: not an archive with fitness and genotypes arrays ({exc})") from exc
    return genotypes[np.isfinite(fitness)]


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``fidelity_table``; exit status 2 for an unreadable map."""
    parser = argparse.ArgumentParser(description="Simulated speeds of the reference gaits per failure scenario, "
                                                 "per engine, and the engines' agreement over a map's gaits.")
    parser.add_argument("--engine", choices=ENGINES + ("both",), default="both", help="engine(s) to tabulate")
    parser.add_argument("--agreement-map", type=Path, default=None,
                        help="archive (.npz) whose gaits the two engines are compared on")
    args = parser.parse_args(argv)
    engines = ENGINES if args.engine == "both" else (args.engine,)
    sims = {name: create_simulator(SimConfig(engine=name)) for name in ENGINES
            if name in engines or args.agreement_map}
    try:
        rows = [row for name in engines for row in fidelity_rows(sims[name])]
        print(markdown(rows))
        if args.agreement_map:
            genotypes = map_genotypes(args.agreement_map)
            a = agreement(genotypes, sims["pybullet"], sims["mujoco"])
            print(f"\nagreement over the {a.gaits} gaits of {args.agreement_map} (collisions not fatal): "
                  f"Spearman {a.spearman:.3f}, mean |descriptor difference| {a.mean_abs_descriptor:.3f}")
    except ValueError as exc:
        print(f"fidelity_table: {exc}", file=sys.stderr)
        return 2
    finally:
        for sim in sims.values():
            sim.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
