# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The adaptation study (README.md)."""
