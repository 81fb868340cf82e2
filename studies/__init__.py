# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Studies of the product: tuning runs and analyses (programs that import the library)."""
