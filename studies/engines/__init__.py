# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The engines study (README.md)."""
