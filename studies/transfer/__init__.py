# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The transfer study (README.md)."""
