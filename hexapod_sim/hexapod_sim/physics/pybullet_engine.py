# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The PyBullet engine (thesis section 3.5): the reference engine and ``sim_node``'s default.

One physics client per simulator, reused. A reset rebuilds the world in that client
(resetSimulation + loading the primitive-shape URDF: 4.4 ms measured) rather than restoring a
saved state: restoreState leaves Bullet's persistent contact manifolds, whose warm-start
impulses made a reused simulator diverge from a fresh one; a rebuilt world is bit for bit a
fresh one. The 18 joint commands go out in one call per step. Collision geometry comes from
hexapod_description's URDF (primitives), loaded with its inertias, self-collision on, the
massless foot frames merged into the tibias, and the femur-base collision filter of 3.5.3.
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass
import os
import tempfile
from typing import Any

from hexapod_description import N_LEGS, urdf_path
from hexapod_sim.damage import DEAD_SERVO_FRICTION, LOST_TIBIA_MASS
from hexapod_sim.engine_settings import PyBulletSettings, servo_kp
from hexapod_sim.shortened import shortened_urdf
from hexapod_sim.simulator import GRAVITY, SimConfig, Simulator, StepReport
import numpy as np
import pybullet as p
import pybullet_data


@contextlib.contextmanager
def _quiet_stdout():
    """Silence C stdout while loading: PyBullet's URDF loader prints link merging there."""
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


@dataclass(frozen=True)
class _Rows:
    """Prepared rows: the healthy legs' position targets as Python lists (PyBullet's fastest)."""

    q: list


class PyBulletSimulator(Simulator):
    """The hexapod in PyBullet."""

    engine = 'pybullet'

    def __init__(self, config: SimConfig | None = None):
        super().__init__(config)
        self.settings: PyBulletSettings
        self._urdf = self._whole_urdf = str(self.model.path if self.config.urdf else urdf_path())
        self._short_urdf: str | None = None  # a temporary URDF with shortened tibias
        self._short_fractions: dict[int, float] = {}
        self.client = p.connect(p.GUI if self.config.gui else p.DIRECT)
        if self.client < 0:
            raise RuntimeError('could not connect to a PyBullet physics server')
        self._build_world()
        cid = self.client
        by_name = {
            p.getJointInfo(self.body, i, physicsClientId=cid)[1].decode(): i
            for i in range(p.getNumJoints(self.body, physicsClientId=cid))
        }
        self.joint_indices = [by_name[name] for name in self.model.joint_names]
        self._link_names = {
            i: p.getJointInfo(self.body, i, physicsClientId=cid)[12].decode()
            for i in by_name.values()
        }
        self._link_names[-1] = 'base_link'
        self._foot_links = [self.joint_indices[3 * leg + 2] for leg in range(N_LEGS)]
        self._foot_leg = {link: leg for leg, link in enumerate(self._foot_links)}
        self.efforts = [lim.effort for lim in self.model.limits]
        # servo 'rx': the shared servo model's gains (studies/engines, item 3 of "Where the
        # engines differ")
        self._rx = self.settings.servo == 'rx'
        self._kp_whole = np.array(
            [servo_kp(e, self.settings.compliance_slope) for e in self.efforts]
        )
        # back-EMF damping effort / velocity limit [N m s/rad], as an explicit step applies it
        self._back_emf = np.array([lim.effort / lim.velocity for lim in self.model.limits])
        self._damping_whole = self._back_emf
        self._target = np.zeros(3 * N_LEGS)
        self._torque = np.zeros(3 * N_LEGS)
        self._tibia_mass = [
            p.getDynamicsInfo(self.body, self._foot_links[leg], physicsClientId=cid)[0]
            for leg in range(N_LEGS)
        ]
        self._configure_world()
        self._set_active_slots()
        self._motors_on = True

    # -- world -------------------------------------------------------------------------------
    def _build_world(self) -> None:
        """(Re)create gravity, engine settings, the ground and the robot in this client."""
        cid, eng = self.client, self.settings
        p.resetSimulation(
            p.RESET_USE_DISCRETE_DYNAMICS_WORLD if eng.discrete_world else 0, physicsClientId=cid
        )
        p.setGravity(0.0, 0.0, -GRAVITY, physicsClientId=cid)
        p.setTimeStep(
            eng.time_step / eng.substeps if eng.servo == 'rx' else eng.time_step,
            physicsClientId=cid,
        )
        p.setPhysicsEngineParameter(
            numSolverIterations=eng.solver_iterations,
            enableConeFriction=int(eng.cone_friction),
            solverResidualThreshold=eng.residual_threshold,
            deterministicOverlappingPairs=1,
            physicsClientId=cid,
        )
        with _quiet_stdout():
            self.plane = p.loadURDF(
                os.path.join(pybullet_data.getDataPath(), 'plane.urdf'), physicsClientId=cid
            )
            flags = (
                p.URDF_USE_INERTIA_FROM_FILE | p.URDF_USE_SELF_COLLISION | p.URDF_MERGE_FIXED_LINKS
            )
            self.body = p.loadURDF(self._urdf, [0.0, 0.0, 0.3], flags=flags, physicsClientId=cid)

    def _configure_world(self) -> None:
        """Joint velocity limits, friction, collision filters (after every rebuild)."""
        cid = self.client
        if not self._rx:
            # the position motor's speed limit. Not with servo 'rx': its back-EMF limits the
            # speed as the servo's does, and Bullet's clamp takes a joint's speed away without
            # a force, so momentum is not kept (it flung a self-colliding gait 7 m:
            # studies/engines/README.md)
            for index, lim in zip(self.joint_indices, self.model.limits):
                p.changeDynamics(
                    self.body, index, maxJointVelocity=lim.velocity, physicsClientId=cid
                )
        # Bullet multiplies two surfaces' coefficients: feet 1 and the floor the configured one
        # meet at exactly SimConfig.friction.
        for leg in range(N_LEGS):
            p.changeDynamics(
                self.body, self._foot_links[leg], lateralFriction=1.0, physicsClientId=cid
            )
            # Section 3.5.3: the femurs would hit the (convex) base before their joint limits.
            p.setCollisionFilterPair(
                self.body, self.body, -1, self.joint_indices[3 * leg + 1], 0, physicsClientId=cid
            )
        p.changeDynamics(self.plane, -1, lateralFriction=self.config.friction, physicsClientId=cid)
        self._apply_failure_filters()

    def _apply_failure_filters(self) -> None:
        """Collision filters and the tibias' masses of the damage (after every rebuild)."""
        cid = self.client
        for leg in range(1, N_LEGS + 1):
            coxa, tibia = self.joint_indices[3 * (leg - 1)], self.joint_indices[3 * (leg - 1) + 2]
            kind = self.damage.kind_of(leg)
            # In the folded failure pose the tibia's bounding box overlaps its own coxa's (the
            # real servo clamps near -150 deg there). A failed leg is a rigid dead weight, so
            # that pair is exempt from collision while the leg is failed.
            folded = kind in ('lifted', 'unpowered')
            p.setCollisionFilterPair(
                self.body, self.body, coxa, tibia, int(not folded), physicsClientId=cid
            )
            # a lost tibia touches nothing and weighs (almost) nothing
            lost = kind == 'no_tibia'
            p.setCollisionFilterGroupMask(
                self.body, tibia, 0 if lost else 1, 0 if lost else -1, physicsClientId=cid
            )
            mass = LOST_TIBIA_MASS if lost else self._tibia_mass[leg - 1]
            if p.getDynamicsInfo(self.body, tibia, physicsClientId=cid)[0] != mass:
                p.changeDynamics(self.body, tibia, mass=mass, physicsClientId=cid)

    def _set_active_slots(self) -> None:
        held = set(self._held_slots.tolist()) | set(self.damage.dead_slots().tolist())
        self._active_slots = [s for s in range(3 * N_LEGS) if s not in held]
        self._active_joints = [self.joint_indices[s] for s in self._active_slots]
        strength = [self.damage.strength_of(s // 3 + 1) for s in self._active_slots]
        self._active_efforts = [self.efforts[s] * k for s, k in zip(self._active_slots, strength)]
        # weak servos: a lower gain (PyBullet's default position gain is 0.1); None: defaults
        weak = any(k != 1.0 for k in strength)
        self._active_gains = [0.1 * k for k in strength] if weak else None
        if self._rx:  # gain and stall torque scaled by strength; dead servos give none
            scale = np.array([self.damage.strength_of(s // 3 + 1) for s in range(3 * N_LEGS)])
            self._kp, self._effort = self._kp_whole * scale, np.array(self.efforts) * scale
            self._damping = self._damping_whole.copy()
            dead = self.damage.dead_slots()
            self._kp[dead] = self._effort[dead] = self._damping[dead] = 0.0

    def _apply_failed_legs(self) -> None:
        urdf = self._damaged_urdf()
        if urdf != self._urdf:  # a tibia shortened or restored: the robot is loaded anew
            self._urdf = urdf
            self._rebuild_keeping_state()
        self._apply_failure_filters()
        if self._rx:  # a lost or shortened tibia has another inertia
            self._implicit_damping()
        self._set_active_slots()
        self._command_failure_pose()

    def _damaged_urdf(self) -> str:
        """Return the URDF of the damage: the whole robot's, or one with shortened tibias."""
        fractions = {d.leg: d.strength for d in self.damage.legs if d.kind == 'shortened'}
        if fractions and fractions == self._short_fractions:
            return self._urdf
        self._short_fractions = fractions
        if self._short_urdf is not None:
            with contextlib.suppress(OSError):
                os.unlink(self._short_urdf)
            self._short_urdf = None
        if not fractions:
            return self._whole_urdf
        with open(self._whole_urdf) as f:
            text = shortened_urdf(f.read(), fractions)
        fd, path = tempfile.mkstemp(suffix='.urdf', prefix='shortened_')
        with os.fdopen(fd, 'w') as f:
            f.write(text)
        self._short_urdf = path
        return path

    def _rebuild_keeping_state(self) -> None:
        """Load the robot anew (a changed URDF) where it was, moving as it moved."""
        cid, body = self.client, self.body
        pos, orn = p.getBasePositionAndOrientation(body, physicsClientId=cid)
        lin, ang = p.getBaseVelocity(body, physicsClientId=cid)
        joints = p.getJointStates(body, self.joint_indices, physicsClientId=cid)
        self._build_world()
        self._configure_world()
        p.resetBasePositionAndOrientation(self.body, pos, orn, physicsClientId=cid)
        p.resetBaseVelocity(self.body, lin, ang, physicsClientId=cid)
        for index, state in zip(self.joint_indices, joints):
            p.resetJointState(self.body, index, state[0], state[1], physicsClientId=cid)

    def _motors_off(self) -> None:
        """Switch Bullet's joint motors off: no torque on any joint until commanded again."""
        p.setJointMotorControlArray(
            self.body,
            self.joint_indices,
            p.VELOCITY_CONTROL,
            forces=[0.0] * len(self.joint_indices),
            physicsClientId=self.client,
        )

    def _command_failure_pose(self) -> None:
        """Drive the held legs (lifted, locked) to their pose; leave dead joints free."""
        dead = self.damage.dead_slots().tolist()
        if self._rx:  # torques each substep: Bullet's motors off, but the dead joints' friction
            self._motors_off()
        if dead:  # no torque: only the friction of the back-driven gearbox
            p.setJointMotorControlArray(
                self.body,
                [self.joint_indices[s] for s in dead],
                p.VELOCITY_CONTROL,
                targetVelocities=[0.0] * len(dead),
                forces=[DEAD_SERVO_FRICTION] * len(dead),
                physicsClientId=self.client,
            )
        if self._rx and self._held_slots.size:
            self._target[self._held_slots] = self._held_values
        if self._rx or not self._held_slots.size:
            return
        slots = self._held_slots.tolist()
        p.setJointMotorControlArray(
            self.body,
            [self.joint_indices[s] for s in slots],
            p.POSITION_CONTROL,
            targetPositions=self._held_values.tolist(),
            targetVelocities=[0.0] * len(slots),
            forces=[self.efforts[s] for s in slots],
            physicsClientId=self.client,
        )

    def _reset_state(self, q: np.ndarray, body_height: float) -> None:
        cid = self.client
        self._build_world()
        self._configure_world()
        p.resetBasePositionAndOrientation(
            self.body, [0.0, 0.0, body_height], [0.0, 0.0, 0.0, 1.0], physicsClientId=cid
        )
        p.resetBaseVelocity(self.body, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], physicsClientId=cid)
        for index, value in zip(self.joint_indices, q.tolist()):
            p.resetJointState(self.body, index, value, 0.0, physicsClientId=cid)
        if self._rx:
            self._target = np.array(q, dtype=float)
            self._implicit_damping()
        self._command_failure_pose()

    def _implicit_damping(self) -> None:
        """
        Scale the back-EMF damping as an implicit step would apply it (servo 'rx').

        Bullet adds joint torques explicitly, and the back-EMF damping c of a light tibia
        (c h / I about 2.4 at 960 Hz) makes an explicit step diverge: the control tripod flew
        off at 4 substeps and walked only at 16 (measured). An implicit step applies
        c / (1 + c h / I) to the velocity the step starts with (DART integrates its damping
        implicitly). I is each joint's diagonal of the mass matrix in the pose of the last reset
        or damage (it moves with the pose; that pose's is taken until the next).
        """
        cid = self.client
        q = [s[0] for s in p.getJointStates(self.body, self.joint_indices, physicsClientId=cid)]
        inertia = np.diag(np.array(p.calculateMassMatrix(self.body, q, physicsClientId=cid)))
        h = self.settings.time_step / self.settings.substeps
        c = self._back_emf
        joints = inertia[6:]  # after the floating base's 6 degrees of freedom
        self._damping_whole = c / (1.0 + c * h / joints)
        self._set_active_slots()

    # -- commands and steps --------------------------------------------------------------------
    def prepare_rows(self, positions: np.ndarray, velocities: np.ndarray) -> Any:
        if self._rx:  # all 18 targets; apply_row takes the active ones
            return np.clip(np.atleast_2d(positions), self.lower, self.upper)
        slots = self._active_slots
        q = np.clip(np.atleast_2d(positions), self.lower, self.upper)[:, slots]
        # ``velocities`` go unused: the servos get position targets only (see apply_row)
        return _Rows(q.tolist())

    def apply_row(self, rows: Any, index: int) -> None:
        # position targets only, as the thesis's simulator commands them (its listing 3.6) and
        # the firmware drives the servos: no velocity feed-forward (the target velocity is 0)
        if self._rx:
            self._target[self._active_slots] = rows[index][self._active_slots]
            return
        p.setJointMotorControlArray(
            self.body,
            self._active_joints,
            p.POSITION_CONTROL,
            targetPositions=rows.q[index],
            forces=self._active_efforts,
            **({} if self._active_gains is None else {'positionGains': self._active_gains}),
            physicsClientId=self.client,
        )

    def set_motor_power(self, on: bool) -> None:
        if on and not self._motors_on:
            # power back: the failed legs' servos hold their pose again
            self._command_failure_pose()
        self._motors_on = bool(on)

    def step(self) -> StepReport:
        if self._rx:
            return self._step_rx()
        if not self._motors_on:  # servo power off: no motor torque on any joint this step
            self._motors_off()
        p.stepSimulation(physicsClientId=self.client)
        self.time += self.dt
        return self._read_contacts()

    def _step_rx(self) -> StepReport:
        """One time step of ``substeps`` physics steps, the servo torque from each one's state."""
        cid, body, joints = self.client, self.body, self.joint_indices
        for _ in range(self.settings.substeps):
            if self._motors_on:
                states = p.getJointStates(body, joints, physicsClientId=cid)
                q = np.array([s[0] for s in states])
                qd = np.array([s[1] for s in states])
                # the servo's torque (what joint_states reports, as MuJoCo and DART report
                # theirs), and its back-EMF, which those two apply as joint damping
                self._torque = np.clip(self._kp * (self._target - q), -self._effort, self._effort)
                applied = self._torque - self._damping * qd
            else:  # servo power off: no torque, no back-EMF (the driver is off)
                self._torque = applied = np.zeros(3 * N_LEGS)
            p.setJointMotorControlArray(
                body, joints, p.TORQUE_CONTROL, forces=applied.tolist(), physicsClientId=cid
            )
            p.stepSimulation(physicsClientId=cid)
        self.time += self.dt
        return self._read_contacts()

    def _read_contacts(self) -> StepReport:
        r = self.report
        r.contacts = [False] * N_LEGS
        r.body_ground = None
        r.self_collision = None
        r.unstable = False
        foot_leg, names = self._foot_leg, self._link_names
        for c in p.getContactPoints(bodyA=self.body, physicsClientId=self.client):
            if c[2] == self.body:
                if r.self_collision is None:
                    r.self_collision = f'{names.get(c[3], c[3])} / {names.get(c[4], c[4])}'
            else:
                leg = foot_leg.get(c[3])
                if leg is None:
                    if r.body_ground is None:
                        r.body_ground = names.get(c[3], str(c[3]))
                else:
                    r.contacts[leg] = True
        return r

    # -- readings -------------------------------------------------------------------------------
    def base_pose(self) -> tuple[np.ndarray, np.ndarray]:
        pos, quat = p.getBasePositionAndOrientation(self.body, physicsClientId=self.client)
        return np.array(pos), np.array(quat)

    def base_velocity(self) -> tuple[np.ndarray, np.ndarray]:
        lin, ang = p.getBaseVelocity(self.body, physicsClientId=self.client)
        return np.array(lin), np.array(ang)

    def link_poses(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        cid = self.client
        # getBasePositionAndOrientation gives the base's inertial frame: undo its local offset
        pos, quat = p.getBasePositionAndOrientation(self.body, physicsClientId=cid)
        local_pos, local_orn = p.getDynamicsInfo(self.body, -1, physicsClientId=cid)[3:5]
        inv_pos, inv_orn = p.invertTransform(local_pos, local_orn)
        base_pos, base_orn = p.multiplyTransforms(pos, quat, inv_pos, inv_orn)
        poses = {'base_link': (np.array(base_pos), np.array(base_orn))}
        for index, name in self._link_names.items():
            if index >= 0:
                state = p.getLinkState(
                    self.body, index, computeForwardKinematics=True, physicsClientId=cid
                )
                poses[name] = (np.array(state[4]), np.array(state[5]))  # the URDF link frame
        return poses

    def link_masses(self) -> dict[str, float]:
        cid = self.client
        return {
            name: float(p.getDynamicsInfo(self.body, index, physicsClientId=cid)[0])
            for index, name in self._link_names.items()
        }

    def joint_states(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        states = p.getJointStates(self.body, self.joint_indices, physicsClientId=self.client)
        return (
            np.array([s[0] for s in states]),
            np.array([s[1] for s in states]),
            self._torque.copy() if self._rx else np.array([s[3] for s in states]),
        )

    def render(
        self,
        width: int = 480,
        height: int = 360,
        distance: float = 0.9,
        yaw: float = 30.0,
        pitch: float = -25.0,
    ) -> np.ndarray:
        pos, _ = self.base_pose()
        view = p.computeViewMatrixFromYawPitchRoll(pos.tolist(), distance, yaw, pitch, 0.0, 2)
        proj = p.computeProjectionMatrixFOV(50.0, width / height, 0.01, 20.0)
        img = p.getCameraImage(
            width, height, view, proj, renderer=p.ER_TINY_RENDERER, physicsClientId=self.client
        )
        return np.reshape(np.asarray(img[2], dtype=np.uint8), (height, width, 4))[:, :, :3]

    def close(self) -> None:
        if getattr(self, '_short_urdf', None) is not None:
            with contextlib.suppress(OSError):
                os.unlink(self._short_urdf)
            self._short_urdf = None
        if getattr(self, 'client', -1) >= 0:
            with contextlib.suppress(p.error):
                p.disconnect(physicsClientId=self.client)
            self.client = -1
