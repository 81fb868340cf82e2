"""``ros2 run hexapod_sim fidelity_table``: print the fidelity table (markdown)."""
from __future__ import annotations

import argparse
import sys

from hexapod_sim.fidelity import fidelity_rows, markdown
from hexapod_sim.simulator import ACCURATE, FAST, HexapodSimulator, SimConfig


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Simulated speeds of the reference gaits per failure scenario.")
    parser.add_argument("--engine", choices=("accurate", "fast"), default="accurate")
    args = parser.parse_args(argv)
    with HexapodSimulator(SimConfig(engine=ACCURATE if args.engine == "accurate" else FAST)) as sim:
        print(markdown(fidelity_rows(sim)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
