# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Read the hexapod model (geometry, joint order, limits, masses) from the URDF.

The URDF is the single source of truth: nothing here restates a number from the thesis
tables; every value is parsed from ``urdf/hexapod.urdf``. ROS-free (no rclpy import).
"""

from __future__ import annotations

from dataclasses import dataclass
import functools
import math
import os
from pathlib import Path
import xml.etree.ElementTree as ET

PACKAGE = 'hexapod_description'
N_LEGS = 6
JOINTS_PER_LEG = 3


def share_path(*parts: str) -> Path:
    """
    Path of a file this package installs in its share directory (``urdf/...``, ``config/...``).

    The installed share directory (ament index) when it holds the file, else the source tree
    next to this module.
    """
    try:
        from ament_index_python.packages import get_package_share_directory, PackageNotFoundError

        try:
            candidate = Path(get_package_share_directory(PACKAGE)).joinpath(*parts)
            if candidate.is_file():
                return candidate
        except (PackageNotFoundError, OSError):  # OSError: no AMENT_PREFIX_PATH at all
            pass
    except ImportError:  # plain Python without the ROS wheels
        pass
    return Path(__file__).resolve().parent.parent.joinpath(*parts)


def urdf_path() -> Path:
    """
    Path of the hexapod URDF.

    ``$HEXAPOD_URDF`` if set, else the package's ``urdf/hexapod.urdf`` (see :func:`share_path`).
    """
    return _user_urdf() or share_path('urdf', 'hexapod.urdf')


def _user_urdf() -> Path | None:
    """``$HEXAPOD_URDF``, a user's whole description, if set."""
    override = os.environ.get('HEXAPOD_URDF')
    return Path(override) if override else None


def robot_description_path() -> Path:
    """
    Path of the URDF that ROS is shown (``robot_description``, ``/tf_static``).

    The physics model (:func:`urdf_path`, which the simulators load and maps record the hash of)
    plus massless sensor frames (``imu_link``): ``urdf/hexapod_robot.urdf``, or ``$HEXAPOD_URDF``
    if set (a user's whole description).
    """
    return _user_urdf() or share_path('urdf', 'hexapod_robot.urdf')


@dataclass(frozen=True)
class JointLimit:
    """Limits of one revolute joint, in URDF units (rad, N m, rad/s)."""

    name: str
    lower: float
    upper: float
    effort: float
    velocity: float


@dataclass(frozen=True)
class LegMount:
    """Pose of a leg's coxa joint in ``base_link``: position [m] and yaw [rad]."""

    leg: int
    x: float
    y: float
    z: float
    yaw: float


@dataclass(frozen=True)
class HexapodModel:
    """Everything the gait controller and the simulator need from the URDF."""

    path: Path
    joint_names: tuple[str, ...]  # 18 revolute joints, leg 1..6, coxa/femur/tibia
    limits: tuple[JointLimit, ...]  # same order as joint_names
    mounts: tuple[LegMount, ...]  # legs 1..6
    coxa_length: float  # a1: coxa joint -> femur joint [m]
    femur_length: float  # a2: femur joint -> tibia joint [m]
    tibia_length: float  # a3: tibia joint -> foot tip [m]
    link_masses: dict[str, float]  # every link's mass [kg]

    @property
    def link_lengths(self) -> tuple[float, float, float]:
        """(a1, a2, a3) of eqs. 3.41 and 3.48-3.50 [m]."""
        return (self.coxa_length, self.femur_length, self.tibia_length)

    @property
    def total_mass(self) -> float:
        """Sum of every link's mass [kg]."""
        return sum(self.link_masses.values())

    @property
    def max_walking_speed(self) -> float:
        """
        Return the fastest the body can walk on its feet [m/s]: no measured trial is faster.

        A foot in stance stands on the floor, so the body moves at most as fast as a foot moves
        relative to it: each joint at its velocity limit (the servo's no-load speed, URDF table
        3.9) times its longest lever to the foot (coxa a1+a2+a3, femur a2+a3, tibia a3), summed,
        for the fastest leg.
        """
        a1, a2, a3 = self.link_lengths
        levers = (a1 + a2 + a3, a2 + a3, a3)
        return max(
            sum(
                self.limit(j).velocity * lever
                for j, lever in zip(self.leg_joint_names(leg), levers)
            )
            for leg in range(1, N_LEGS + 1)
        )

    def limit(self, joint_name: str) -> JointLimit:
        """Return the limits of joint ``joint_name``."""
        return self.limits[self.joint_names.index(joint_name)]

    def leg_joint_names(self, leg: int) -> tuple[str, str, str]:
        """(coxa, femur, tibia) joint names of leg 1..6."""
        if not 1 <= leg <= N_LEGS:
            raise ValueError(f'leg must be 1..{N_LEGS}, got {leg}')
        i = (leg - 1) * JOINTS_PER_LEG
        return self.joint_names[i], self.joint_names[i + 1], self.joint_names[i + 2]


def _floats(text: str | None, n: int, default: float = 0.0) -> tuple[float, ...]:
    if text is None:
        return (default,) * n
    values = tuple(float(v) for v in text.split())
    if len(values) != n:
        raise ValueError(f'expected {n} numbers, got {text!r}')
    return values


def _origin(joint: ET.Element) -> tuple[tuple[float, ...], tuple[float, ...]]:
    origin = joint.find('origin')
    if origin is None:
        return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    return _floats(origin.get('xyz'), 3), _floats(origin.get('rpy'), 3)


def parse_model(path: Path) -> HexapodModel:
    """Parse a hexapod URDF. Raises ValueError naming what is missing or malformed."""
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise ValueError(f'{path} is not a URDF (XML): {exc}') from None
    joints = {j.get('name'): j for j in root.findall('joint')}
    links = {link.get('name'): link for link in root.findall('link')}

    names: list[str] = []
    limits: list[JointLimit] = []
    mounts: list[LegMount] = []
    lengths: dict[str, list[float]] = {'coxa': [], 'femur': [], 'tibia': []}
    for leg in range(1, N_LEGS + 1):
        for k in range(1, JOINTS_PER_LEG + 1):
            name = f'joint_{leg}_{k}'
            joint = joints.get(name)
            if joint is None or joint.get('type') != 'revolute':
                raise ValueError(f'{path}: revolute joint {name} missing')
            lim = joint.find('limit')
            if lim is None:
                raise ValueError(f'{path}: joint {name} has no <limit>')
            limits.append(
                JointLimit(
                    name,
                    float(lim.get('lower')),
                    float(lim.get('upper')),
                    float(lim.get('effort')),
                    float(lim.get('velocity')),
                )
            )
            names.append(name)
        xyz, rpy = _origin(joints[f'joint_{leg}_1'])
        mounts.append(LegMount(leg, xyz[0], xyz[1], xyz[2], rpy[2]))
        lengths['coxa'].append(_origin(joints[f'joint_{leg}_2'])[0][0])
        lengths['femur'].append(_origin(joints[f'joint_{leg}_3'])[0][0])
        foot = joints.get(f'joint_{leg}_foot')
        if foot is None:
            raise ValueError(f'{path}: fixed joint joint_{leg}_foot (tibia tip) missing')
        lengths['tibia'].append(_origin(foot)[0][0])
    for part, values in lengths.items():
        if max(values) - min(values) > 1e-12:
            raise ValueError(f'{path}: legs disagree on the {part} length: {values}')

    masses: dict[str, float] = {}
    for name, link in links.items():
        mass = link.find('inertial/mass')
        masses[name] = float(mass.get('value')) if mass is not None else 0.0

    return HexapodModel(
        path=Path(path),
        joint_names=tuple(names),
        limits=tuple(limits),
        mounts=tuple(mounts),
        coxa_length=lengths['coxa'][0],
        femur_length=lengths['femur'][0],
        tibia_length=lengths['tibia'][0],
        link_masses=masses,
    )


@functools.lru_cache(maxsize=4)
def _load_cached(path: str) -> HexapodModel:
    return parse_model(Path(path))


def load_model(path: Path | str | None = None) -> HexapodModel:
    """Return the hexapod model, parsed once per path and cached."""
    return _load_cached(str(path if path is not None else urdf_path()))


def summary(model: HexapodModel | None = None) -> str:
    """Return a human-readable summary of the model (used by ``describe`` and ``make demo``)."""
    m = model or load_model()
    lines = [
        f'URDF: {m.path}',
        f'total mass: {m.total_mass:.3f} kg ({len(m.link_masses)} links)',
        'link lengths a1/a2/a3: ' + ' / '.join(f'{v * 1000:.2f} mm' for v in m.link_lengths),
        'leg mounts (x, y, z [m], yaw [deg]):',
    ]
    for mount in m.mounts:
        lines.append(
            f'  leg {mount.leg}: ({mount.x:+.4f}, {mount.y:+.4f}, {mount.z:+.4f}) '
            f'{math.degrees(mount.yaw):6.1f}'
        )
    lines.append('joints (lower..upper rad, effort N m, velocity rad/s):')
    for lim in m.limits[:JOINTS_PER_LEG]:
        lines.append(
            f'  {lim.name.replace("_1_", "_n_")}: {lim.lower:+.3f}..{lim.upper:+.3f}, '
            f'{lim.effort:.3f}, {lim.velocity:.3f}'
        )
    return '\n'.join(lines)
