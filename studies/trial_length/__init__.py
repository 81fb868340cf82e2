# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The trial length study (README.md)."""
