"""PyBullet simulator of the hexapod (thesis section 3.5); ROS-free.

One physics client is created per simulator and reused. A reset rebuilds the world in that
client (resetSimulation + loading the primitive-shape URDF: 4.4 ms measured) rather than
restoring a saved state: restoreState leaves Bullet's persistent contact manifolds, whose
warm-start impulses made a reused simulator diverge from a fresh one; a rebuilt world is bit
for bit a fresh one. The 18 joint commands go out in one call per step and the step loop
allocates no NumPy arrays. Collision geometry comes from hexapod_description's
URDF (primitives), loaded with its inertias, self-collision on, the massless foot frames
merged into the tibias, and the femur-base collision filter of section 3.5.3.
"""
from __future__ import annotations

import contextlib
import math
import os
from dataclasses import dataclass, field
from typing import Iterable, Sequence

import numpy as np
import pybullet as p
import pybullet_data

from hexapod_description import load_model, urdf_path

N_LEGS = 6
#: Failure pose of a leg (thesis table 5.1): coxa 0, femur 90, tibia -165 degrees.
FAILURE_POSE = (0.0, math.radians(90.0), math.radians(-165.0))
MAX_FAILED_LEGS = 2
GRAVITY = 9.81


@dataclass(frozen=True)
class EngineSettings:
    """Physics-engine settings. ``ACCURATE`` is PyBullet's default and the default everywhere.
    ``FAST`` trades solver iterations for speed; ``make bench-sim`` measures its ranking
    fidelity against ACCURATE, which does not reach Spearman 0.95 (see docs/simulator.md), so
    nothing uses it unless asked to."""

    solver_iterations: int = 50
    time_step: float = 1.0 / 240.0
    cone_friction: bool = True
    #: PyBullet's default world also runs deformable-body machinery; the plain discrete
    #: multibody world skips it (no effect on rigid-body results).
    discrete_world: bool = False
    #: Solver stops iterating early once the squared residual is below this (PyBullet: 1e-7).
    residual_threshold: float = 1e-7

    def __post_init__(self) -> None:
        if self.solver_iterations < 1:
            raise ValueError(f"solver_iterations must be >= 1, got {self.solver_iterations}")
        if not 0 < self.time_step <= 0.01:
            raise ValueError(f"time_step must be in (0, 0.01] s, got {self.time_step}")


ACCURATE = EngineSettings()
FAST = EngineSettings(solver_iterations=20)


@dataclass(frozen=True)
class SimConfig:
    friction: float = 1.0                 # lateral friction of the ground and the feet
    engine: EngineSettings = ACCURATE
    gui: bool = False
    urdf: str | None = None               # default: hexapod_description's URDF

    def __post_init__(self) -> None:
        if not (math.isfinite(self.friction) and 0.0 <= self.friction <= 10.0):
            raise ValueError(f"friction must be in [0, 10], got {self.friction}")


def validate_failed_legs(legs: Iterable[int]) -> tuple[int, ...]:
    """Sorted, de-duplicated legs 1..6, at most two; ValueError says what is wrong."""
    out = []
    for leg in legs:
        if isinstance(leg, bool) or not isinstance(leg, (int, np.integer)):
            raise ValueError(f"leg numbers must be integers 1..6, got {leg!r}")
        if not 1 <= int(leg) <= N_LEGS:
            raise ValueError(f"leg {leg} does not exist: legs are numbered 1..6")
        out.append(int(leg))
    legs_t = tuple(sorted(set(out)))
    if len(legs_t) > MAX_FAILED_LEGS:
        raise ValueError(f"at most {MAX_FAILED_LEGS} legs can fail (the thesis scenarios S0-S4); "
                         f"got {len(legs_t)}: {list(legs_t)}")
    return legs_t


@contextlib.contextmanager
def _quiet_stdout():
    """PyBullet's URDF loader prints link merging to C stdout; silence it while loading."""
    try:
        saved = os.dup(1)
    except OSError:
        yield
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)
        os.close(devnull)


@dataclass
class StepReport:
    """What happened in the last step (reused object; copy what you keep)."""

    contacts: list = field(default_factory=lambda: [False] * N_LEGS)   # per leg, foot on ground
    body_ground: int | None = None      # link index (-1 base) of a non-foot link on the ground
    self_collision: tuple[int, int] | None = None                   # colliding link pair


class HexapodSimulator:
    """The hexapod on a flat plane, stepped at ``config.engine.time_step``."""

    def __init__(self, config: SimConfig | None = None):
        self.config = config or SimConfig()
        self.model = load_model(self.config.urdf) if self.config.urdf else load_model()
        eng = self.config.engine
        self.dt = eng.time_step
        self._urdf = str(self.model.path if self.config.urdf else urdf_path())
        self.client = p.connect(p.GUI if self.config.gui else p.DIRECT)
        if self.client < 0:
            raise RuntimeError("could not connect to a PyBullet physics server")
        self.failed_legs: tuple[int, ...] = ()
        self._build_world()
        cid = self.client
        by_name = {p.getJointInfo(self.body, i, physicsClientId=cid)[1].decode(): i
                   for i in range(p.getNumJoints(self.body, physicsClientId=cid))}
        self.joint_indices = [by_name[name] for name in self.model.joint_names]
        self.link_names = {i: p.getJointInfo(self.body, i, physicsClientId=cid)[12].decode() for i in by_name.values()}
        self.link_names[-1] = "base_link"
        self.foot_links = [self.joint_indices[3 * leg + 2] for leg in range(N_LEGS)]
        self._foot_leg = {link: leg for leg, link in enumerate(self.foot_links)}
        self.efforts = [lim.effort for lim in self.model.limits]
        self.lower = np.array([lim.lower for lim in self.model.limits])
        self.upper = np.array([lim.upper for lim in self.model.limits])
        self.max_velocity = np.array([lim.velocity for lim in self.model.limits])
        self._configure_world()
        self._active_joint_slots = list(range(3 * N_LEGS))
        self._active_joint_indices = list(self.joint_indices)
        self._active_efforts = list(self.efforts)
        self.report = StepReport()
        self.time = 0.0
        self._prev_velocity = np.zeros(3)
        self._accel = np.array([0.0, 0.0, 0.0])

    def _build_world(self) -> None:
        """(Re)create gravity, engine settings, the ground and the robot in this client."""
        cid, eng = self.client, self.config.engine
        p.resetSimulation(p.RESET_USE_DISCRETE_DYNAMICS_WORLD if eng.discrete_world else 0, physicsClientId=cid)
        p.setGravity(0.0, 0.0, -GRAVITY, physicsClientId=cid)
        p.setTimeStep(eng.time_step, physicsClientId=cid)
        p.setPhysicsEngineParameter(numSolverIterations=eng.solver_iterations,
                                    enableConeFriction=int(eng.cone_friction),
                                    solverResidualThreshold=eng.residual_threshold,
                                    deterministicOverlappingPairs=1, physicsClientId=cid)
        with _quiet_stdout():
            self.plane = p.loadURDF(os.path.join(pybullet_data.getDataPath(), "plane.urdf"), physicsClientId=cid)
            flags = p.URDF_USE_INERTIA_FROM_FILE | p.URDF_USE_SELF_COLLISION | p.URDF_MERGE_FIXED_LINKS
            self.body = p.loadURDF(self._urdf, [0.0, 0.0, 0.3], flags=flags, physicsClientId=cid)

    def _configure_world(self) -> None:
        """Joint velocity limits, friction, collision filters (after every rebuild)."""
        cid = self.client
        for index, lim in zip(self.joint_indices, self.model.limits):
            p.changeDynamics(self.body, index, maxJointVelocity=lim.velocity, physicsClientId=cid)
        for leg in range(N_LEGS):
            p.changeDynamics(self.body, self.foot_links[leg], lateralFriction=self.config.friction, physicsClientId=cid)
            # Section 3.5.3: the femurs would hit the (convex) base before their joint limits.
            p.setCollisionFilterPair(self.body, self.body, -1, self.joint_indices[3 * leg + 1], 0, physicsClientId=cid)
        p.changeDynamics(self.plane, -1, lateralFriction=self.config.friction, physicsClientId=cid)
        self._apply_failure_filters()

    def _apply_failure_filters(self) -> None:
        for leg in range(1, N_LEGS + 1):
            coxa, tibia = self.joint_indices[3 * (leg - 1)], self.joint_indices[3 * (leg - 1) + 2]
            # In the folded failure pose the tibia's bounding box overlaps its own coxa's (the
            # real servo clamps near -150 deg there). A failed leg is a rigid dead weight, so
            # that pair is exempt from collision while the leg is failed.
            p.setCollisionFilterPair(self.body, self.body, coxa, tibia, int(leg not in self.failed_legs),
                                     physicsClientId=self.client)

    # -- configuration ----------------------------------------------------------------------
    def set_failed_legs(self, legs: Iterable[int]) -> tuple[int, ...]:
        """Hold these legs (1..6, at most two) in the failure pose (table 5.1), from now on:
        their motors drive them to the pose; a reset places them there directly."""
        new = validate_failed_legs(legs)
        self.failed_legs = new
        self._apply_failure_filters()
        failed_slots = {3 * (leg - 1) + k for leg in self.failed_legs for k in range(3)}
        self._active_joint_slots = [s for s in range(3 * N_LEGS) if s not in failed_slots]
        self._active_joint_indices = [self.joint_indices[s] for s in self._active_joint_slots]
        self._active_efforts = [self.efforts[s] for s in self._active_joint_slots]
        self._command_failure_pose()
        return self.failed_legs

    def _command_failure_pose(self) -> None:
        if not self.failed_legs:
            return
        slots = [3 * (leg - 1) + k for leg in self.failed_legs for k in range(3)]
        p.setJointMotorControlArray(self.body, [self.joint_indices[s] for s in slots], p.POSITION_CONTROL,
                                    targetPositions=[FAILURE_POSE[s % 3] for s in slots],
                                    targetVelocities=[0.0] * len(slots), forces=[self.efforts[s] for s in slots],
                                    physicsClientId=self.client)

    # -- state ------------------------------------------------------------------------------
    def reset(self, joint_positions: Sequence[float], body_height: float | None = None) -> None:
        """Robot back at the origin (yaw 0) with the given joint angles (18, URDF order); failed
        legs in the failure pose; everything at rest. The base is placed at ``body_height``, by
        default the height that puts the lowest foot on the ground (the gait's body height for
        a gait-controller pose), so every caller starts from bit-identical states."""
        if body_height is None:
            from hexapod_gait import default_kinematics
            from hexapod_gait.trajectory import default_geometry
            from hexapod_sim.trajectory_input import body_height_from_joints

            body_height = body_height_from_joints(joint_positions, default_kinematics(), default_geometry())
        cid = self.client
        self._build_world()
        self._configure_world()
        p.resetBasePositionAndOrientation(self.body, [0.0, 0.0, float(body_height)], [0.0, 0.0, 0.0, 1.0],
                                          physicsClientId=cid)
        p.resetBaseVelocity(self.body, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], physicsClientId=cid)
        q = np.clip(np.asarray(joint_positions, dtype=float), self.lower, self.upper)
        for leg in self.failed_legs:
            q[3 * (leg - 1): 3 * leg] = FAILURE_POSE
        for index, value in zip(self.joint_indices, q.tolist()):
            p.resetJointState(self.body, index, value, 0.0, physicsClientId=cid)
        self._command_failure_pose()
        self.time = 0.0
        self._prev_velocity = np.zeros(3)
        self._accel = np.zeros(3)

    def prepare_rows(self, positions: np.ndarray, velocities: np.ndarray) -> tuple[list, list]:
        """Joint tables (N, 18) as the rows :meth:`apply_row` sends: positions clipped to the
        joint limits, velocities to the velocity limits, only the healthy legs' joints. Done once
        per table (and again after the failed legs change), never per step."""
        slots = self._active_joint_slots
        q = np.clip(np.atleast_2d(positions), self.lower, self.upper)[:, slots]
        v = np.clip(np.atleast_2d(velocities), -self.max_velocity, self.max_velocity)[:, slots]
        return q.tolist(), v.tolist()

    def apply_row(self, q_row: list, v_row: list) -> None:
        """Send one prepared row as position-control targets (one call for all joints)."""
        p.setJointMotorControlArray(self.body, self._active_joint_indices, p.POSITION_CONTROL,
                                    targetPositions=q_row, targetVelocities=v_row,
                                    forces=self._active_efforts, physicsClientId=self.client)

    def command(self, positions: Sequence[float], velocities: Sequence[float]) -> None:
        """Position-control targets (18 each, URDF order) for the healthy legs (convenience for
        occasional commands; loops prepare their table once with :meth:`prepare_rows`)."""
        q, v = self.prepare_rows(np.asarray(positions, dtype=float), np.asarray(velocities, dtype=float))
        self.apply_row(q[0], v[0])

    def step(self) -> StepReport:
        """Advance one time step and report foot contacts and collisions."""
        p.stepSimulation(physicsClientId=self.client)
        self.time += self.dt
        return self._read_contacts()

    def _read_contacts(self) -> StepReport:
        r = self.report
        r.contacts = [False] * N_LEGS
        r.body_ground = None
        r.self_collision = None
        foot_leg = self._foot_leg
        for c in p.getContactPoints(bodyA=self.body, physicsClientId=self.client):
            if c[2] == self.body:
                if r.self_collision is None:
                    r.self_collision = (c[3], c[4])
            else:
                leg = foot_leg.get(c[3])
                if leg is None:
                    if r.body_ground is None:
                        r.body_ground = c[3]
                else:
                    r.contacts[leg] = True
        return r

    def update_imu(self) -> None:
        """Update the finite-difference base acceleration (call once per step if IMU
        readings are wanted)."""
        v = np.array(p.getBaseVelocity(self.body, physicsClientId=self.client)[0])
        self._accel = (v - self._prev_velocity) / self.dt
        self._prev_velocity = v

    # -- readings ---------------------------------------------------------------------------
    def base_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """Base position [m] and orientation quaternion (x, y, z, w) in the world frame."""
        pos, quat = p.getBasePositionAndOrientation(self.body, physicsClientId=self.client)
        return np.array(pos), np.array(quat)

    def base_velocity(self) -> tuple[np.ndarray, np.ndarray]:
        """Base linear [m/s] and angular [rad/s] velocity in the world frame."""
        lin, ang = p.getBaseVelocity(self.body, physicsClientId=self.client)
        return np.array(lin), np.array(ang)

    def base_rotation(self) -> np.ndarray:
        """Base-to-world rotation matrix (3, 3)."""
        return np.array(p.getMatrixFromQuaternion(self.base_pose()[1].tolist())).reshape(3, 3)

    def base_twist_body(self) -> tuple[np.ndarray, np.ndarray]:
        """Base linear [m/s] and angular [rad/s] velocity expressed in the base frame."""
        rot = self.base_rotation()
        lin, ang = self.base_velocity()
        return rot.T @ lin, rot.T @ ang

    def imu(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """IMU-like readings in the base frame: orientation quaternion (x, y, z, w), angular
        velocity [rad/s], and specific force [m/s^2] (acceleration minus gravity, what an
        accelerometer measures: +9.81 on z at rest)."""
        _, quat = self.base_pose()
        rot = self.base_rotation()
        _, ang_body = self.base_twist_body()
        specific_force = self._accel + np.array([0.0, 0.0, GRAVITY])
        return quat, ang_body, rot.T @ specific_force

    def joint_states(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Joint positions [rad], velocities [rad/s], applied motor torques [N m] (URDF order)."""
        states = p.getJointStates(self.body, self.joint_indices, physicsClientId=self.client)
        return (np.array([s[0] for s in states]), np.array([s[1] for s in states]),
                np.array([s[3] for s in states]))

    def link_name(self, index: int) -> str:
        return self.link_names.get(index, str(index))

    def render(self, width: int = 480, height: int = 360, distance: float = 0.9,
               yaw: float = 30.0, pitch: float = -25.0) -> np.ndarray:
        """An RGB image (height, width, 3) from the headless renderer, following the robot."""
        pos, _ = self.base_pose()
        view = p.computeViewMatrixFromYawPitchRoll(pos.tolist(), distance, yaw, pitch, 0.0, 2)
        proj = p.computeProjectionMatrixFOV(50.0, width / height, 0.01, 20.0)
        img = p.getCameraImage(width, height, view, proj, renderer=p.ER_TINY_RENDERER,
                               physicsClientId=self.client)
        return np.reshape(np.asarray(img[2], dtype=np.uint8), (height, width, 4))[:, :, :3]

    def close(self) -> None:
        if self.client >= 0:
            with contextlib.suppress(p.error):
                p.disconnect(physicsClientId=self.client)
            self.client = -1

    def __enter__(self) -> "HexapodSimulator":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __del__(self) -> None:
        with contextlib.suppress(Exception):
            self.close()
