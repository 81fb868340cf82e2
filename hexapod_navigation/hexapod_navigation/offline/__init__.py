# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The navigation experiment and the making of the navigation files (damage bank, specialists)."""
