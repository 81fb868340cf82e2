# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The physics engines behind the one simulator interface, and their settings."""
