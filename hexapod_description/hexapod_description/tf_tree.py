# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The URDF's kinematic tree as transforms (what robot_state_publisher computes); ROS-free.

Each joint of the URDF places its child link in its parent's frame: origin (xyz, rpy), then a
rotation about the joint axis by the joint angle (revolute joints). ``fixed`` joints give
static transforms (the foot frames).
"""

from __future__ import annotations

from dataclasses import dataclass
import math
from pathlib import Path
from typing import Mapping
import xml.etree.ElementTree as ET

from hexapod_description.model import urdf_path
import numpy as np

Quaternion = tuple[float, float, float, float]  # (x, y, z, w)


@dataclass(frozen=True)
class JointFrame:
    """One URDF joint: where its child link sits in its parent's frame."""

    name: str
    kind: str  # revolute, fixed, ...
    parent: str
    child: str
    xyz: tuple[float, float, float]  # origin translation [m]
    rotation: Quaternion  # origin rotation (from rpy)
    axis: tuple[float, float, float]  # unit joint axis in the child frame


def quat_from_rpy(roll: float, pitch: float, yaw: float) -> Quaternion:
    """Quaternion (x, y, z, w) of URDF fixed-axis rpy: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    )


def quat_multiply(a: Quaternion, b: Quaternion) -> Quaternion:
    """Return the rotation a then b, both (x, y, z, w): a * b."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def _floats(text: str | None, default: tuple[float, float, float]) -> tuple[float, float, float]:
    if not text:
        return default
    x, y, z = (float(v) for v in text.split())
    return (x, y, z)


def joint_frames(path: str | Path | None = None) -> list[JointFrame]:
    """Every joint of the URDF at ``path`` (default: hexapod_description's), in file order."""
    root = ET.parse(str(path or urdf_path())).getroot()
    frames = []
    for joint in root.findall('joint'):
        origin = joint.find('origin')
        xyz = _floats(origin.get('xyz') if origin is not None else None, (0.0, 0.0, 0.0))
        rpy = _floats(origin.get('rpy') if origin is not None else None, (0.0, 0.0, 0.0))
        axis_el = joint.find('axis')
        axis = np.array(
            _floats(axis_el.get('xyz') if axis_el is not None else None, (1.0, 0.0, 0.0))
        )
        axis = axis / np.linalg.norm(axis)
        frames.append(
            JointFrame(
                joint.get('name'),
                joint.get('type'),
                joint.find('parent').get('link'),
                joint.find('child').get('link'),
                xyz,
                quat_from_rpy(*rpy),
                (float(axis[0]), float(axis[1]), float(axis[2])),
            )
        )
    return frames


def child_transform(
    frame: JointFrame, position: float = 0.0
) -> tuple[tuple[float, float, float], Quaternion]:
    """Return (translation, rotation) of ``frame.child`` in ``frame.parent`` at ``position``."""
    if frame.kind in ('revolute', 'continuous'):
        half = position / 2
        s = math.sin(half)
        turn = (frame.axis[0] * s, frame.axis[1] * s, frame.axis[2] * s, math.cos(half))
        return frame.xyz, quat_multiply(frame.rotation, turn)
    return frame.xyz, frame.rotation


def moving_transforms(
    frames: list[JointFrame], positions: Mapping[str, float]
) -> list[tuple[JointFrame, tuple[float, float, float], Quaternion]]:
    """Return the transforms of the movable joints in ``positions`` (the content of /tf)."""
    return [
        (f, *child_transform(f, positions[f.name]))
        for f in frames
        if f.kind != 'fixed' and f.name in positions
    ]


def static_transforms(
    frames: list[JointFrame],
) -> list[tuple[JointFrame, tuple[float, float, float], Quaternion]]:
    """Return the transforms of the fixed joints (the content of /tf_static)."""
    return [(f, *child_transform(f)) for f in frames if f.kind == 'fixed']
