# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""A part's health, ROS-free: what a node shows on ``/diagnostics`` (:mod:`.diagnostics`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping

OK, WARN, ERROR, STALE = 0, 1, 2, 3  # DiagnosticStatus levels


@dataclass(frozen=True)
class Health:
    """One part's health: ``name`` (as the node names it), level, a sentence, the real part."""

    name: str
    level: int
    message: str
    hardware_id: str
    values: Mapping[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.level not in (OK, WARN, ERROR, STALE):
            raise ValueError(f'level must be OK, WARN, ERROR or STALE (0..3), got {self.level}')
