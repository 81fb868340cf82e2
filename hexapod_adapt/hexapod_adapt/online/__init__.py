# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Adapting online: M-BOA, adaptation runs, the damage-informed prior, ceilings, trials."""
