# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The navigation study (README.md)."""
