# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The map methods study (README.md)."""
