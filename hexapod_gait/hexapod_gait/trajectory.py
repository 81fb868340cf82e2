# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Foot trajectories and the joint table of one gait cycle (thesis section 3.4.3).

Per leg, in its own cycle time tau in [0, T) (tau = ((t/T - phase_offset) mod 1) * T):
  * support, tau in [0, beta*T): a straight line from p_start to p_end at constant velocity
    (eqs. 3.34-3.36);
  * swing, tau in [beta*T, T): the 6th-order polynomial of eqs. 3.19-3.27 from p_end back to
    p_start through the raised mid point p_mid at half the swing time. It is evaluated in
    normalised time s = u / t_f, where it reads
        p(s) = P0 + dm * 64 s^3 (1 - s)^3 + de * (-22 s^3 + 81 s^4 - 90 s^5 + 32 s^6),
    dm = p_mid - P0, de = P1 - P0: the same polynomial as the a0..a6 of eqs. 3.21-3.27.
Key points (eqs. 3.14-3.18) lie in the leg frame at the coxa joint; the walking direction
(crab angle alpha in base_link) appears in leg n's frame at angle alpha - theta_n. With a turn
rate omega (our extension) each leg strides along the motion the body gives its foot-path centre
c: v (cos alpha, sin alpha) + omega z x c, the chord of the arc (omega = 0: the thesis's stride).
Everything is evaluated on arrays (legs x samples); there is no Python loop over time.
"""

from __future__ import annotations

from dataclasses import dataclass
import functools
from types import SimpleNamespace

from hexapod_description import load_model, N_LEGS
from hexapod_gait.kinematics import default_kinematics, LegKinematics
from hexapod_gait.parameters import (
    DEFAULT_CRAB_ANGLE,
    DEFAULT_PERIOD,
    GaitParameters,
    genotype_fields,
)
import numpy as np

#: Largest FK(IK(p)) - p accepted as "reachable" [m] (section 3.4.5).
REACH_TOLERANCE = 1e-6
#: Smallest singularity margin (|sin theta3|, reach/a1) accepted.
SINGULARITY_TOLERANCE = 1e-4
_TIME_DECIMALS = 12  # cycle times are compared at 1e-12 s resolution
SIM_RATE = 240.0  # Hz, PyBullet's step
ROBOT_RATE = 120.0  # Hz, the robot's gait timer (thesis 4.3.1)
#: A newly loaded gait's first pose is reached in this long, the joint targets interpolated from
#: where the legs are (the robot's firmware, docs/radio-protocol.md; the navigator in simulation).
POSE_TRANSITION_S = 0.5


def transition(start: np.ndarray, pose: np.ndarray, duration: float, rate: float) -> np.ndarray:
    """Return joint targets (N, 18) moving linearly from ``start`` to ``pose`` in ``duration``."""
    n = max(1, int(round(duration * rate)))
    start = np.asarray(start, dtype=float)
    return start + np.linspace(1.0 / n, 1.0, n)[:, None] * (np.asarray(pose) - start)


class ReachabilityError(ValueError):
    """A leg cannot follow its foot path (section 3.4.5); names the leg and the time."""

    def __init__(self, leg: int, time: float, period: float, reason: str):
        super().__init__(
            f'leg {leg} cannot follow its foot path at t = {time:.4f} s of the '
            f'{period:g} s cycle: {reason}'
        )
        self.leg = leg
        self.time = time
        self.reason = reason


@dataclass(frozen=True)
class LegGeometry:
    """
    Where the legs are mounted on the body.

    Yaw of each leg frame [rad] and the height of the coxa joints below the base frame origin [m]
    (both from the URDF).
    """

    yaw: np.ndarray  # (6,)
    mount_z: np.ndarray  # (6,)
    mount_xy: np.ndarray  # (6, 2) coxa joint positions in base_link [m]


@functools.lru_cache(maxsize=1)
def default_geometry() -> LegGeometry:
    """Leg mount yaws and heights of the installed hexapod URDF."""
    mounts = load_model().mounts
    return LegGeometry(
        np.array([m.yaw for m in mounts]),
        np.array([m.z for m in mounts]),
        np.array([(m.x, m.y) for m in mounts]),
    )


def key_points(
    params: GaitParameters, geometry: LegGeometry | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """
    (p_start, p_mid, p_end), each (6, 3), in the leg frames (eqs. 3.14-3.18).

    Also works on batches: any object whose per-leg fields are (G, 6) and whose body fields
    are (G, 1) gives (G, 6, 3) arrays.
    """
    geo = geometry or default_geometry()
    centre_x = params.radius * np.cos(params.angle_offset)
    centre_y = params.radius * np.sin(params.angle_offset)
    # body velocity at each foot-path centre, in base_link: v (cos a, sin a) + omega z x c
    cos_yaw, sin_yaw = np.cos(geo.yaw), np.sin(geo.yaw)
    base_cx = geo.mount_xy[:, 0] + cos_yaw * centre_x - sin_yaw * centre_y
    base_cy = geo.mount_xy[:, 1] + sin_yaw * centre_x + cos_yaw * centre_y
    turn = getattr(params, 'turn_rate', 0.0)
    vx = params.body_velocity * np.cos(params.crab_angle) - turn * base_cy
    vy = params.body_velocity * np.sin(params.crab_angle) + turn * base_cx
    # the stride (eq. 3.17 with that velocity) turned into the leg frame
    scale = params.period * params.duty_factor
    half_x = 0.5 * scale * (cos_yaw * vx + sin_yaw * vy)
    half_y = 0.5 * scale * (-sin_yaw * vx + cos_yaw * vy)
    ground = -(params.body_height + geo.mount_z) + np.zeros_like(centre_x)  # -h_b + 0.014
    start = np.stack([centre_x + half_x, centre_y + half_y, ground], axis=-1)
    end = np.stack([centre_x - half_x, centre_y - half_y, ground], axis=-1)
    mid = np.stack([centre_x, centre_y, ground + params.step_height], axis=-1)
    return start, mid, end


def reachable_key_points(
    genotypes: np.ndarray,
    kinematics: LegKinematics | None = None,
    geometry: LegGeometry | None = None,
) -> np.ndarray:
    """
    (G,) bool: every leg's three key points are reachable.

    A cheap necessary condition for :func:`build_joint_table` to succeed, for filtering many random
    genotypes at once.
    """
    kin = kinematics or default_kinematics()
    fields = {'crab_angle': DEFAULT_CRAB_ANGLE, 'turn_rate': 0.0}
    fields.update(genotype_fields(genotypes))  # an omni genotype brings its own
    batch = SimpleNamespace(period=DEFAULT_PERIOD, **fields)
    points = np.stack(key_points(batch, geometry), axis=-2)  # (G, 6, 3, 3)
    angles = kin.inverse(points)
    ok = (kin.reach_error(points, angles) <= REACH_TOLERANCE) & (
        kin.singularity_margin(angles) >= SINGULARITY_TOLERANCE
    )
    return ok.all(axis=(-1, -2))


def leg_cycle_time(params: GaitParameters, times: np.ndarray) -> np.ndarray:
    """Each leg's own cycle time tau (6, N) [s] at the given times (N,)."""
    t = np.asarray(times, dtype=float)
    tau = np.mod(t[None, :] / params.period - params.phase_offset[:, None], 1.0) * params.period
    # Round away float noise so a sample that lies exactly on a phase boundary (e.g. phase
    # 0.5, duty 5/6) falls on the same side for every leg; then wrap T back to 0.
    return np.mod(np.round(tau, _TIME_DECIMALS), params.period)


def stance_mask(params: GaitParameters, times: np.ndarray) -> np.ndarray:
    """(N, 6) bool: True where the leg is in its support (stance) phase."""
    tau = leg_cycle_time(params, times)
    return (tau < np.round(params.duty_factor[:, None] * params.period, _TIME_DECIMALS)).T


def foot_trajectory(
    params: GaitParameters, times: np.ndarray, geometry: LegGeometry | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Foot positions (6, N, 3) [m], velocities (6, N, 3) [m/s] and stance (6, N) at times (N,)."""
    start, mid, end = key_points(params, geometry)
    period = params.period
    tau = leg_cycle_time(params, times)  # (6, N)
    t_support = params.duty_factor[:, None] * period  # (6, 1)
    t_swing = period - t_support
    stance = tau < np.round(t_support, _TIME_DECIMALS)

    # Support: linear start -> end.
    # (6, 3)
    support_velocity = np.divide(
        end - start, t_support, out=np.zeros_like(start), where=t_support > 0
    )
    support_pos = start[:, None, :] + support_velocity[:, None, :] * tau[..., None]

    # Swing: polynomial end -> mid -> start in normalised time s.
    tf = np.where(t_swing > 0, t_swing, 1.0)
    s = np.clip((tau - t_support) / tf, 0.0, 1.0)[..., None]  # (6, N, 1)
    dm = (mid - end)[:, None, :]
    de = (start - end)[:, None, :]
    s2 = s * s
    s3 = s2 * s
    one_minus = 1.0 - s
    pm = 64.0 * s3 * one_minus**3
    pe = s3 * (-22.0 + s * (81.0 + s * (-90.0 + 32.0 * s)))
    dpm = 192.0 * s2 * one_minus**2 * (1.0 - 2.0 * s)
    dpe = s2 * (-66.0 + s * (324.0 + s * (-450.0 + 192.0 * s)))
    swing_pos = end[:, None, :] + dm * pm + de * pe
    swing_vel = (dm * dpm + de * dpe) / tf[..., None]

    st = stance[..., None]
    positions = np.where(st, support_pos, swing_pos)
    velocities = np.where(st, support_velocity[:, None, :], swing_vel)
    return positions, velocities, stance


@dataclass(frozen=True)
class JointTable:
    """
    Joint angles and rates of one gait cycle, sampled at ``rate``.

    Row k is time k / rate; columns are the 18 joints in URDF order (leg 1..6, each coxa,
    femur, tibia). Playing the rows cyclically walks the gait.
    """

    rate: float  # Hz
    period: float  # s
    positions: np.ndarray  # (N, 18) rad
    velocities: np.ndarray  # (N, 18) rad/s
    stance: np.ndarray  # (N, 6) bool, legs 1..6

    @property
    def times(self) -> np.ndarray:
        """Sample times of the rows [s]."""
        return np.arange(self.positions.shape[0]) / self.rate

    def __len__(self) -> int:
        return self.positions.shape[0]


def samples_per_cycle(period: float, rate: float) -> int:
    """Return the number of control steps in one cycle; period * rate must be a whole number."""
    n = period * rate
    steps = int(round(n))
    if steps < 2 or abs(n - steps) > 1e-6 * max(1.0, n):
        raise ValueError(
            f'period {period:g} s x rate {rate:g} Hz = {n:g} samples: '
            'must be a whole number of at least 2'
        )
    return steps


def build_joint_table(
    params: GaitParameters,
    rate: float = SIM_RATE,
    kinematics: LegKinematics | None = None,
    geometry: LegGeometry | None = None,
) -> JointTable:
    """
    Joint table of one cycle at ``rate`` Hz.

    Raises :class:`ReachabilityError` if a foot point cannot be reached or lies on a kinematic
    singularity.
    """
    kin = kinematics or default_kinematics()
    n = samples_per_cycle(params.period, rate)
    times = np.arange(n) / rate
    feet, foot_vel, stance = foot_trajectory(params, times, geometry)
    angles = kin.inverse(feet)  # (6, N, 3)

    bad = kin.reach_error(feet, angles) > REACH_TOLERANCE
    if bad.any():
        leg, k = np.unravel_index(int(np.argmax(bad)), bad.shape)
        miss = float(kin.reach_error(feet[leg, k], angles[leg, k]))
        raise ReachabilityError(
            int(leg) + 1,
            float(times[k]),
            params.period,
            f'foot point out of reach by {miss * 1000:.1f} mm',
        )
    margin = kin.singularity_margin(angles)
    bad = margin < SINGULARITY_TOLERANCE
    if bad.any():
        leg, k = np.unravel_index(int(np.argmax(bad)), bad.shape)
        raise ReachabilityError(
            int(leg) + 1,
            float(times[k]),
            params.period,
            'kinematic singularity (leg fully stretched or foot on the coxa axis)',
        )
    rates = kin.joint_velocities(angles, foot_vel)
    return JointTable(
        rate=float(rate),
        period=params.period,
        positions=np.ascontiguousarray(angles.transpose(1, 0, 2).reshape(n, 3 * N_LEGS)),
        velocities=np.ascontiguousarray(rates.transpose(1, 0, 2).reshape(n, 3 * N_LEGS)),
        stance=np.ascontiguousarray(stance.T),
    )
