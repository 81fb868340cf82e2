# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Leg kinematics of the thesis (section 3.4.4-3.4.6), vectorised over any number of points.

Frames: each leg's frame sits at its coxa joint with x pointing radially out and z up
(fig. 3.5). Angles are (theta1 coxa, theta2 femur, theta3 tibia) in radians; positive theta2
lifts the femur, the knee-down branch (s3 <= 0) of eq. 3.43 is used, as on the robot.
Link lengths come from hexapod_description (the URDF), never retyped here.
"""

from __future__ import annotations

from dataclasses import dataclass
import functools

from hexapod_description import load_model
import numpy as np


@dataclass(frozen=True)
class LegKinematics:
    """Closed-form kinematics of one 3-DOF leg with link lengths a1, a2, a3 [m]."""

    a1: float
    a2: float
    a3: float

    def forward(self, angles: np.ndarray) -> np.ndarray:
        """Foot position (..., 3) from joint angles (..., 3); eqs. 3.48-3.50."""
        t1, t2, t3 = np.moveaxis(np.asarray(angles, dtype=float), -1, 0)
        reach = self.a1 + self.a3 * np.cos(t2 + t3) + self.a2 * np.cos(t2)
        return np.stack(
            [
                np.cos(t1) * reach,
                np.sin(t1) * reach,
                self.a3 * np.sin(t2 + t3) + self.a2 * np.sin(t2),
            ],
            axis=-1,
        )

    def inverse(self, points: np.ndarray) -> np.ndarray:
        """
        Joint angles (..., 3) for foot positions (..., 3); eqs. 3.38-3.43.

        Points out of reach give angles whose forward kinematics miss the point (c3 is
        clipped to [-1, 1]); :meth:`reach_error` measures that miss.
        """
        x, y, z = np.moveaxis(np.asarray(points, dtype=float), -1, 0)
        t1 = np.arctan2(y, x)
        c1, s1 = np.cos(t1), np.sin(t1)
        rho2 = (x - self.a1 * c1) ** 2 + (y - self.a1 * s1) ** 2
        c3 = (rho2 + z * z - self.a2**2 - self.a3**2) / (2.0 * self.a2 * self.a3)
        c3 = np.clip(c3, -1.0, 1.0)
        s3 = -np.sqrt(1.0 - c3 * c3)
        t2 = np.arctan2(z, np.sqrt(rho2)) - np.arctan2(self.a3 * s3, self.a2 + self.a3 * c3)
        t3 = np.arctan2(s3, c3)
        return np.stack([t1, t2, t3], axis=-1)

    def joint_velocities(self, angles: np.ndarray, foot_velocities: np.ndarray) -> np.ndarray:
        """
        Joint rates (..., 3) [rad/s] for foot velocities (..., 3) [m/s]; eqs. 3.44-3.46.

        Singular where s3 = 0 (leg straight) or the foot is on the coxa axis; callers check
        :meth:`singularity_margin` first.
        """
        t1, t2, t3 = np.moveaxis(np.asarray(angles, dtype=float), -1, 0)
        dx, dy, dz = np.moveaxis(np.asarray(foot_velocities, dtype=float), -1, 0)
        c1, s1 = np.cos(t1), np.sin(t1)
        c2, s2 = np.cos(t2), np.sin(t2)
        c3, s3 = np.cos(t3), np.sin(t3)
        c23 = np.cos(t2 + t3)
        radial = dz * s2 + dx * c1 * c2 + dy * c2 * s1
        tangential = dz * c2 - dx * c1 * s2 - dy * s1 * s2
        w1 = (dy * c1 - dx * s1) / (self.a1 + self.a3 * c23 + self.a2 * c2)
        w2 = (tangential + (c3 / s3) * radial) / self.a2
        w3 = -(tangential + ((self.a2 + self.a3 * c3) / (self.a3 * s3)) * radial) / self.a2
        return np.stack([w1, w2, w3], axis=-1)

    def singularity_margin(self, angles: np.ndarray) -> np.ndarray:
        """
        min(|sin theta3|, horizontal reach from the coxa axis / a1) per point.

        Near 0 the joint-velocity equations blow up.
        """
        t2, t3 = np.asarray(angles, dtype=float)[..., 1], np.asarray(angles, dtype=float)[..., 2]
        reach = self.a1 + self.a3 * np.cos(t2 + t3) + self.a2 * np.cos(t2)
        return np.minimum(np.abs(np.sin(t3)), np.abs(reach) / self.a1)

    def reach_error(self, points: np.ndarray, angles: np.ndarray) -> np.ndarray:
        """|FK(angles) - points| per point [m] (the check of section 3.4.5)."""
        return np.linalg.norm(self.forward(angles) - np.asarray(points, dtype=float), axis=-1)


@functools.lru_cache(maxsize=1)
def default_kinematics() -> LegKinematics:
    """Kinematics with the link lengths of the installed hexapod URDF."""
    a1, a2, a3 = load_model().link_lengths
    return LegKinematics(a1, a2, a3)
