# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The byte-level protocols: the radio's legacy frames and extension, the Xsens IMU's Xbus."""
