# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The engine-neutral simulator interface (thesis section 3.5); ROS-free.

Every loop that steps physics (gait evaluation, ``sim_node``, ``render_walk``, the robot
emulator) talks to a :class:`Simulator`. Two engines implement it:

* ``pybullet`` (:mod:`hexapod_sim.physics.pybullet_engine`): the thesis's engine, the reference and
  the default of ``sim_node``;
* ``mujoco`` (:mod:`hexapod_sim.physics.mujoco_engine`): the fast engine for maps and large
  experiments;
* ``dart`` (:mod:`hexapod_sim.physics.dart_engine`): the judge, for reporting only; it takes no
  part in making a map, choosing a method, tuning a setting or choosing a default.

All load ``hexapod_description``'s URDF. Engine internals (clients, bodies, ``MjData``) stay in
the engine modules; nothing else touches them. :func:`create_simulator` picks the engine named in
:class:`SimConfig`.
"""

from __future__ import annotations

import abc
from dataclasses import asdict, dataclass, field, replace
import hashlib
import json
import math
from typing import Any, Iterable, Sequence

from hexapod_description import load_model, N_LEGS
from hexapod_description.model import HexapodModel
from hexapod_gait import default_kinematics
from hexapod_gait.trajectory import default_geometry
from hexapod_sim.damage import (  # noqa: F401 (re-exported: one home, hexapod_sim.damage)
    as_damage,
    Damage,
    FAILURE_POSE,
    MAX_FAILED_LEGS,
    validate_failed_legs,
)
from hexapod_sim.engine_settings import (
    ACCURATE,
    DART_DEFAULT_SETTINGS,
    DEFAULT_SETTINGS,
    MUJOCO_VARIANT_DEFAULTS,
)
import numpy as np

GRAVITY = 9.81
#: Roll or pitch beyond this [deg] means the robot has tipped over (a hexapod on its side or
#: back does not right itself); navigation fails a goal there, map figures count a tipped gait.
TIP_OVER_DEG = 60.0
ENGINES = ('pybullet', 'mujoco', 'dart')
#: The engine that judges maps: it takes no part in making or tuning them (docs/simulator.md).
JUDGE_ENGINE = 'dart'
#: Physics steps per 240 Hz row at which each engine's speeds of a map's fast gaits have
#: converged (studies/engines, "Where the engines differ", item 6: within a median 0.015 m/s of
#: the finest step and Spearman >= 0.95). A map's figures on another engine are measured there
#: (:meth:`SimConfig.converged`); the engines' defaults are cheaper.
CONVERGED_SUBSTEPS = {'pybullet': 16, 'mujoco': 4, 'dart': 16}


def validate_engine(name: str) -> str:
    """Return the engine name, or ValueError listing the known engines."""
    if name not in ENGINES:
        raise ValueError(f'unknown physics engine {name!r}; choose one of: {", ".join(ENGINES)}')
    return name


def body_height_from_joints(q: np.ndarray) -> float:
    """
    Return the base height that puts the lowest foot on the ground for joint angles q (18,).

    The inverse of the controller's foot height -(h_b + mount_z). One definition for every engine,
    ``sim_node`` and the emulator, so they all start from identical states.
    """
    feet = default_kinematics().forward(np.asarray(q, dtype=float).reshape(N_LEGS, 3))
    return float(np.max(-(feet[:, 2] + default_geometry().mount_z)))


def start_height(
    commanded: Sequence[float], held_slots: np.ndarray, held_values: np.ndarray
) -> float:
    """
    Return the base height a reset starts at: the lowest foot on the ground.

    The commanded feet's, raised if a held leg (a locked one, at the standing pose) reaches
    lower: its foot would start inside the floor, and the contact throws it out (on PyBullet
    the body is flung past 60 degrees; studies/diagnosis/README.md, "Locked legs started inside
    the floor"). A held leg above the commanded feet (a lifted one) changes nothing: the robot
    drops onto them as before (at most 50 mm, which moves a walk's speed by at most 2.3 mm/s:
    the same README), so walks under every other damage are unchanged
    (:data:`HELD_START_VERSION`).
    """
    height = body_height_from_joints(np.asarray(commanded, dtype=float))
    if len(held_slots) == 0:
        return height
    held = np.array(commanded, dtype=float)
    held[held_slots] = held_values
    return max(height, body_height_from_joints(held))


#: The version of :func:`start_height`'s rule for damage with a locked leg, the only kind whose
#: held pose can reach below the commanded feet (2: raised onto it; before, started in the
#: floor). Cached walks under such damage carry it in their key (:func:`start_key`).
HELD_START_VERSION = 2


def start_key(damages: Iterable[Damage]) -> dict[str, int]:
    """Return what a cache of walks under ``damages`` adds to its key for the start rule."""
    if any(leg.kind == 'locked' for damage in damages for leg in damage.legs):
        return {'held_start': HELD_START_VERSION}
    return {}


#: Friction coefficient where a foot meets the floor, on every engine (SimConfig.friction's
#: default): 1, the thesis's (3.5.4, listing 3.5: "a lateralFriction coefficient of 1 ... for the
#: ground plane and the tibia links"). Each engine combines two surfaces' coefficients its own way,
#: so each sets its surfaces to give exactly this at the contact (studies/engines, "Where the
#: engines differ"). The robot's floor is unmeasured and slipperier (thesis 5.5.5): set your own.
FRICTION = 1.0


@dataclass(frozen=True)
class SimConfig:
    """
    Which engine, with which settings.

    ``friction`` is the coefficient where a foot meets the floor, the same on every engine (None:
    :data:`FRICTION`); each engine's own choices live in its settings object.
    """

    engine: str = 'pybullet'
    friction: float | None = None
    pybullet: Any = None  # PyBulletSettings (default: engine_settings.ACCURATE)
    mujoco: Any = None  # MujocoSettings (default: engine_settings.DEFAULT_SETTINGS)
    dart: Any = None  # DartSettings (default: engine_settings.DART_DEFAULT_SETTINGS)
    gui: bool = False  # PyBullet only: open its GUI window
    urdf: str | None = None  # default: hexapod_description's URDF

    def __post_init__(self) -> None:
        validate_engine(self.engine)
        if self.friction is None:
            object.__setattr__(self, 'friction', FRICTION)
        if not (math.isfinite(self.friction) and 0.0 <= self.friction <= 10.0):
            raise ValueError(f'friction must be in [0, 10], got {self.friction}')

    def with_substeps(self, substeps: int) -> 'SimConfig':
        """Return this configuration with its engine at ``substeps`` physics steps per row."""
        settings = replace(self.engine_settings(), substeps=substeps)
        return replace(self, **{self.engine: settings})

    @classmethod
    def converged(cls, engine: str) -> 'SimConfig':
        """Return ``engine`` at :data:`CONVERGED_SUBSTEPS`: where a map's figures are measured."""
        return cls(engine=validate_engine(engine)).with_substeps(CONVERGED_SUBSTEPS[engine])

    def engine_settings(self) -> Any:
        """Return the settings object of the selected engine (its default if none was given)."""
        if self.engine == 'pybullet':
            return self.pybullet or ACCURATE
        if self.engine == 'dart':
            return self.dart or DART_DEFAULT_SETTINGS
        return self.mujoco or DEFAULT_SETTINGS

    def fingerprint(self) -> dict[str, Any]:
        """
        Return what a simulated result depends on besides the gait.

        Engine, its settings (and their hash), friction. Recorded in archive metadata.
        """
        settings = asdict(self.engine_settings())
        if self.engine == 'mujoco':
            # as before these fields existed: the maps, ceilings and banks made then stay valid
            added_later = {'substeps': 1, **MUJOCO_VARIANT_DEFAULTS}
            for name, value in added_later.items():
                if settings[name] == value:
                    del settings[name]
        blob = json.dumps(
            {'engine': self.engine, 'settings': settings, 'friction': self.friction},
            sort_keys=True,
        ).encode()
        return {
            'engine': self.engine,
            'settings': settings,
            'friction': self.friction,
            'settings_sha256': hashlib.sha256(blob).hexdigest(),
        }


def fingerprint_substeps(fingerprint: dict[str, Any]) -> int | None:
    """
    Return the physics steps per row a :meth:`SimConfig.fingerprint` records (None if unknown).

    A MuJoCo fingerprint without them was made at 1 (the fingerprint leaves 1 out).
    """
    settings = fingerprint.get('settings')
    if not isinstance(settings, dict):
        return None
    substeps = settings.get('substeps')
    if substeps is None and fingerprint.get('engine') == 'mujoco':
        return 1
    return substeps if isinstance(substeps, int) and substeps > 0 else None


@dataclass
class StepReport:
    """What happened in the last step (reused object; copy what you keep)."""

    contacts: list = field(default_factory=lambda: [False] * N_LEGS)  # per leg, foot on ground
    body_ground: str | None = None  # name of a non-foot link on the ground
    self_collision: str | None = None  # description of a self-collision
    unstable: bool = False  # the engine's numbers blew up this step (and were reset)

    @property
    def collision(self) -> str | None:
        """Return a description of the first collision of this step, or None."""
        if self.self_collision is not None:
            return f'self-collision {self.self_collision}'
        if self.body_ground is not None:
            return f'{self.body_ground} touched the ground'
        return None


@dataclass(frozen=True)
class JointRows:
    """
    A joint table to play cyclically.

    Positions and velocities (N, 18), URDF order, one row per simulator step.
    """

    positions: np.ndarray
    velocities: np.ndarray


@dataclass(frozen=True)
class PlayResult:
    """The outcome of playing a joint table from a reset (:meth:`Simulator.rollout`)."""

    steps: int  # steps simulated (fewer than asked if stopped on a collision)
    contact_steps: np.ndarray  # (6,) steps with each foot on the ground
    collision_steps: int  # steps with a collision
    first_collision: str | None  # "<what> at t = <s> s", or None
    final_position: np.ndarray  # (3,) base position at the end [m]
    contacts: np.ndarray | None = None  # (steps, 6) bool, if recorded
    unstable: str | None = None  # why the engine's numbers cannot be trusted, or None
    final_orientation: np.ndarray | None = None  # (4,) base quaternion (x, y, z, w) at the end
    peak_tilt: float = 0.0  # rad: the largest |roll| or |pitch| over the steps (if recorded)


def quat_to_matrix(quat: Sequence[float]) -> np.ndarray:
    """Rotation matrix (3, 3) of a unit quaternion (x, y, z, w)."""
    x, y, z, w = (float(v) for v in quat)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def matrix_to_quat(r: np.ndarray) -> np.ndarray:
    """Return the unit quaternion (x, y, z, w) of a rotation matrix (3, 3), as quat_to_matrix's."""
    t = r[0, 0] + r[1, 1] + r[2, 2]
    if t > 0:
        s = 2.0 * np.sqrt(t + 1.0)
        q = [(r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, s / 4]
    elif r[0, 0] > r[1, 1] and r[0, 0] > r[2, 2]:
        s = 2.0 * np.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2])
        q = [s / 4, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s, (r[2, 1] - r[1, 2]) / s]
    elif r[1, 1] > r[2, 2]:
        s = 2.0 * np.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2])
        q = [(r[0, 1] + r[1, 0]) / s, s / 4, (r[1, 2] + r[2, 1]) / s, (r[0, 2] - r[2, 0]) / s]
    else:
        s = 2.0 * np.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1])
        q = [(r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, s / 4, (r[1, 0] - r[0, 1]) / s]
    q = np.array(q)
    return q / np.linalg.norm(q)


def upside_down(quat: Sequence[float]) -> bool:
    """
    Whether a base orientation (x, y, z, w) has the body's up axis below the horizontal.

    A robot that ends a trial like this fell over (its IMU sees it): the trial is a fall, not a
    walk, whatever distance the engine moved it (PyBullet can slide a robot on its back metres).
    """
    x, y, _, _ = (float(v) for v in quat)
    return 1.0 - 2.0 * (x * x + y * y) < 0.0  # z of the body's z axis in the world frame


def peak_tilt(quats: np.ndarray) -> float:
    """Return the largest |roll| or |pitch| [rad] over quaternions (n, 4) (x, y, z, w)."""
    x, y, z, w = np.asarray(quats, dtype=float).reshape(-1, 4).T
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))  # as quat_to_euler
    pitch = np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0))
    return float(np.max(np.maximum(np.abs(roll), np.abs(pitch)), initial=0.0))


def quat_to_euler(quat: Sequence[float]) -> tuple[float, float, float]:
    """
    (roll, pitch, yaw) [rad] of a quaternion (x, y, z, w).

    Rotations about fixed x, y, z applied in that order (the convention of PyBullet's
    getEulerFromQuaternion and REP 103).
    """
    x, y, z, w = (float(v) for v in quat)
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return roll, pitch, yaw


class Simulator(abc.ABC):
    """
    The hexapod on a flat plane, stepped at ``dt``: one interface, three engines.

    Joint vectors are 18 long in URDF order (``model.joint_names``). Failed legs (1..6, at most
    two) are held by their servos in the pose of table 5.1 as dead weight; a reset keeps them.
    """

    engine: str
    dt: float
    model: HexapodModel
    failed_legs: tuple[int, ...]
    damage: Damage
    report: StepReport

    def __init__(self, config: SimConfig | None) -> None:
        self.config = config or SimConfig(engine=self.engine)
        if self.config.engine != self.engine:
            raise ValueError(
                f'{type(self).__name__} runs the {self.engine} engine, not {self.config.engine}'
            )
        self.settings = self.config.engine_settings()
        self.dt = float(self.settings.time_step)
        self.model = load_model(self.config.urdf) if self.config.urdf else load_model()
        self.lower = np.array([lim.lower for lim in self.model.limits])
        self.upper = np.array([lim.upper for lim in self.model.limits])
        self.max_velocity = np.array([lim.velocity for lim in self.model.limits])
        self.failed_legs = ()
        self.damage = Damage()
        self._held_slots, self._held_values = self.damage.held_slots()
        self.report = StepReport()
        self.time = 0.0
        self._prev_velocity = np.zeros(3)
        self._accel = np.zeros(3)

    # -- what each engine implements -------------------------------------------------------------
    @abc.abstractmethod
    def _apply_failed_legs(self) -> None:
        """Make the engine apply ``self.damage`` from now on (held slots already set)."""

    @abc.abstractmethod
    def _reset_state(self, q: np.ndarray, body_height: float) -> None:
        """Robot at (0, 0, body_height), yaw 0, joints q (failed legs already posed), at rest."""

    @abc.abstractmethod
    def prepare_rows(self, positions: np.ndarray, velocities: np.ndarray) -> Any:
        """
        Return a joint table (N, 18) in the engine's own form for :meth:`apply_row`.

        Positions clipped to the joint limits, velocities to the velocity limits, the failed legs'
        joints left to the failure pose. Done once per table, never per step.
        """

    @abc.abstractmethod
    def apply_row(self, rows: Any, index: int) -> None:
        """Command row ``index`` of prepared rows (one call for all joints)."""

    @abc.abstractmethod
    def step(self) -> StepReport:
        """Advance one time step; report foot contacts and collisions of that step."""

    @abc.abstractmethod
    def set_motor_power(self, on: bool) -> None:
        """Servo power on or off (off: no servo torque, as after the firmware's e-stop)."""

    @abc.abstractmethod
    def base_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """Return the base position [m] and orientation (x, y, z, w) in the world frame."""

    @abc.abstractmethod
    def base_velocity(self) -> tuple[np.ndarray, np.ndarray]:
        """Return the base linear [m/s] and angular [rad/s] velocity in the world frame."""

    @abc.abstractmethod
    def link_poses(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """
        World pose of every link frame of the URDF (``base_link`` and ``link_<leg>_<k>``).

        Position [m] and quaternion (x, y, z, w).
        """

    @abc.abstractmethod
    def link_masses(self) -> dict[str, float]:
        """Mass of every body as the engine loaded it [kg] (foot frames fused into the tibias)."""

    @abc.abstractmethod
    def joint_states(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Joint positions [rad], velocities [rad/s], servo torques [N m] (URDF order)."""

    @abc.abstractmethod
    def render(
        self,
        width: int = 480,
        height: int = 360,
        distance: float = 0.9,
        yaw: float = 30.0,
        pitch: float = -25.0,
    ) -> np.ndarray:
        """Return an RGB image (height, width, 3) from a camera following the robot."""

    @abc.abstractmethod
    def close(self) -> None:
        """Release the engine's resources (idempotent)."""

    def rollout(
        self,
        tables: Sequence[JointRows],
        n_steps: int,
        stop_on_collision: bool = False,
        record_contacts: bool = False,
        record_tilt: bool = False,
    ) -> list[PlayResult]:
        """
        Play each table cyclically for ``n_steps`` from a reset to its first row (damage kept).

        The default steps in Python; an engine may run the batch natively. Afterwards the simulator
        is in the final state of the last table. ``record_tilt``: each result's ``peak_tilt``
        (otherwise 0: the map's evaluations do not pay for it).
        """
        return [
            self._play(t, n_steps, stop_on_collision, record_contacts, record_tilt) for t in tables
        ]

    # -- shared behaviour ------------------------------------------------------------------------
    def _position_targets(self, positions: np.ndarray) -> np.ndarray:
        """Return position rows (N, 18) clipped to the limits, the held legs at their pose."""
        q = np.clip(np.atleast_2d(np.asarray(positions, dtype=float)), self.lower, self.upper)
        if self._held_slots.size:
            q[:, self._held_slots] = self._held_values
        return np.ascontiguousarray(q)

    def set_failed_legs(self, legs: Iterable[int]) -> tuple[int, ...]:
        """
        Hold these legs (1..6, at most two) in the failure pose (table 5.1), from now on.

        Their servos drive them to the pose; a reset places them there directly.
        """
        return self.set_damage(Damage.lifted(legs)).failed_legs

    def set_damage(self, damage: Damage | Iterable[int]) -> Damage:
        """
        Apply ``damage`` (a :class:`Damage`, or leg numbers to lift), from now on.

        It replaces any earlier damage; ``Damage()`` repairs every leg. Held legs (lifted,
        locked) are driven to their pose by their servos; a reset places them there directly.
        """
        self.damage = as_damage(damage)
        self.failed_legs = self.damage.failed_legs
        self._held_slots, self._held_values = self.damage.held_slots()
        self._apply_failed_legs()
        return self.damage

    def reset(self, joint_positions: Sequence[float], body_height: float | None = None) -> None:
        """
        Put the robot back at the origin (yaw 0), at rest, with the given joint angles.

        Angles are clipped to the limits; held legs (lifted, locked) go to their pose. The base is
        placed at ``body_height``, by default the height that puts the lowest commanded foot on
        the ground, or higher if a held leg reaches lower (:func:`start_height`).
        """
        q = np.clip(np.asarray(joint_positions, dtype=float), self.lower, self.upper)
        if body_height is None:
            body_height = start_height(joint_positions, self._held_slots, self._held_values)
        q[self._held_slots] = self._held_values
        self._reset_state(q, float(body_height))
        self.time = 0.0
        self._prev_velocity = np.zeros(3)
        self._accel = np.zeros(3)

    def command(self, positions: Sequence[float], velocities: Sequence[float]) -> None:
        """
        Servo targets (18 each) for the healthy legs.

        Occasional commands; loops prepare their table once with :meth:`prepare_rows`.
        """
        self.apply_row(
            self.prepare_rows(
                np.atleast_2d(np.asarray(positions, dtype=float)),
                np.atleast_2d(np.asarray(velocities, dtype=float)),
            ),
            0,
        )

    def update_imu(self) -> None:
        """
        Update the finite-difference base acceleration.

        Call once per step if IMU readings are wanted.
        """
        v = self.base_velocity()[0]
        self._accel = (v - self._prev_velocity) / self.dt
        self._prev_velocity = v

    def base_rotation(self) -> np.ndarray:
        """Base-to-world rotation matrix (3, 3)."""
        return quat_to_matrix(self.base_pose()[1])

    def base_euler(self) -> tuple[float, float, float]:
        """Return the base (roll, pitch, yaw) [rad] in the world frame."""
        return quat_to_euler(self.base_pose()[1])

    def base_twist_body(self) -> tuple[np.ndarray, np.ndarray]:
        """Return the base linear [m/s] and angular [rad/s] velocity in the base frame."""
        rot = self.base_rotation()
        lin, ang = self.base_velocity()
        return rot.T @ lin, rot.T @ ang

    def imu(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """
        IMU-like readings in the base frame.

        Orientation quaternion (x, y, z, w), angular velocity [rad/s], and specific force [m/s^2]
        (acceleration minus gravity, what an accelerometer measures: +9.81 on z at rest).
        """
        _, quat = self.base_pose()
        rot = quat_to_matrix(quat)
        _, ang_body = self.base_twist_body()
        return quat, ang_body, rot.T @ (self._accel + np.array([0.0, 0.0, GRAVITY]))

    def _play(
        self,
        table: JointRows,
        n_steps: int,
        stop_on_collision: bool,
        record_contacts: bool,
        record_tilt: bool = False,
    ) -> PlayResult:
        """Return the per-step loop behind the default :meth:`rollout`."""
        rows = self.prepare_rows(table.positions, table.velocities)
        n_rows = len(table.positions)
        self.reset(table.positions[0])
        counts = np.zeros(N_LEGS, dtype=np.int64)
        record = np.zeros((n_steps, N_LEGS), dtype=bool) if record_contacts else None
        collision_steps, first = 0, None
        steps = n_steps
        attitudes = np.zeros((n_steps, 4)) if record_tilt else None
        for k in range(n_steps):
            self.apply_row(rows, k % n_rows)
            report = self.step()
            if attitudes is not None:
                attitudes[k] = self.base_pose()[1]
            collided = report.collision
            if collided is not None:
                collision_steps += 1
                if first is None:
                    first = f'{collided} at t = {(k + 1) * self.dt:.3f} s'
                if stop_on_collision:
                    steps = k + 1
                    break
            counts += report.contacts
            if record is not None:
                record[k] = report.contacts
        return PlayResult(
            steps,
            counts,
            collision_steps,
            first,
            self.base_pose()[0],
            None if record is None else record[:steps],
            final_orientation=self.base_pose()[1],
            peak_tilt=0.0 if attitudes is None else peak_tilt(attitudes[:steps]),
        )

    def __enter__(self) -> 'Simulator':
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # noqa: BLE001 - interpreter shutdown: nothing left to release into
            pass
