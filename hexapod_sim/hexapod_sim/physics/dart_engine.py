# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The DART engine: the judge of maps (the engine of the original IT&E hexapod work).

It takes no part in making a map, choosing a method, tuning a setting or choosing a default; its
figures are reported. The robot is loaded from hexapod_description's URDF with DART's URDF loader
(a free joint at the root); the massless foot frames are dropped first (DART would give a body
without inertia a default mass), so the tibias carry their foot spheres as in the other engines.
Contacts are DART's hard, LCP-solved constraints; the narrow phase is ODE's
(:class:`~hexapod_sim.engine_settings.DartSettings`). One step of the interface (1/240 s,
one row of a gait table) is ``substeps`` DART steps; contacts are those of the last one.

Servos: the model every engine shares, torque = clip(kp (q_target - q), -effort, effort)
- (effort / velocity) q_dot, kp from the RX compliance slope. The proportional part is computed
here before every physics step; the back-EMF part is DART's joint damping, which it integrates
implicitly. Damage follows :mod:`hexapod_sim.damage` as the other engines do: held legs by their
servos, weak servos scaled, a lost tibia collides with nothing and weighs
:data:`~hexapod_sim.damage.LOST_TIBIA_MASS`, a dead servo is free with the back-driven gearbox's
Coulomb friction (dartpy exposes no joint armature, so DEAD_SERVO_ARMATURE is not modelled here),
a shortened tibia is cut by :mod:`hexapod_sim.shortened`.
"""

from __future__ import annotations

import re
from typing import Any, Sequence

import dartpy as dart
from hexapod_description import N_LEGS
from hexapod_sim.damage import DEAD_SERVO_FRICTION, LOST_TIBIA_MASS
from hexapod_sim.engine_settings import DartSettings, servo_kp
from hexapod_sim.shortened import TibiaShape
from hexapod_sim.simulator import (
    GRAVITY,
    JointRows,
    matrix_to_quat,
    PlayResult,
    SimConfig,
    Simulator,
    StepReport,
)
import numpy as np

_DETECTORS = {
    'ode': dart.collision.OdeCollisionDetector,
    'bullet': dart.collision.BulletCollisionDetector,
    'fcl': dart.collision.FCLCollisionDetector,
}
_FOOT_LINK = re.compile(r'<link name="link_\d_foot">.*?</link>', re.S)
_FOOT_JOINT = re.compile(r'<joint name="joint_\d_foot".*?</joint>', re.S)
#: A velocity no joint reaches [rad/s]: DART's hard velocity limit lifted.
_NO_LIMIT = 1e6
#: The ground: a box this large, its top face at z = 0.
_GROUND_SIZE = (50.0, 50.0, 0.1)


class DartSimulator(Simulator):
    """The hexapod in DART."""

    engine = 'dart'

    def __init__(self, config: SimConfig | None = None):
        super().__init__(config)
        self.settings: DartSettings
        with open(self.model.path) as f:
            urdf = _FOOT_JOINT.sub('', _FOOT_LINK.sub('', f.read()))
        self.skel = dart.utils.DartLoader().parseSkeletonString(urdf, dart.common.Uri(''))
        self.world = dart.simulation.World()
        self.world.setGravity([0.0, 0.0, -GRAVITY])
        self._substeps = self.settings.substeps
        self.world.setTimeStep(self.dt / self._substeps)
        solver = self.world.getConstraintSolver()
        solver.setCollisionDetector(_DETECTORS[self.settings.collision_detector]())
        self.ground = dart.dynamics.Skeleton('ground')
        _, ground_body = self.ground.createWeldJointAndBodyNodePair()
        ground_shape = ground_body.createShapeNode(dart.dynamics.BoxShape(list(_GROUND_SIZE)))
        ground_shape.createCollisionAspect()
        ground_shape.createDynamicsAspect()
        ground_shape.setRelativeTranslation([0.0, 0.0, -_GROUND_SIZE[2] / 2])
        self.world.addSkeleton(self.ground)
        self.world.addSkeleton(self.skel)
        self.skel.enableSelfCollisionCheck()
        self.skel.disableAdjacentBodyCheck()  # parent and child never collide (as in MuJoCo)
        self._filter = solver.getCollisionOption().collisionFilter
        self._bodies = {
            self.skel.getBodyNode(i).getName(): self.skel.getBodyNode(i)
            for i in range(self.skel.getNumBodyNodes())
        }
        self._base = self._bodies['base_link']
        self._ground_name = ground_body.getName()
        # Section 3.5.3: the femurs would hit the base before their joint limits.
        for leg in range(1, N_LEGS + 1):
            self._filter.addBodyNodePairToBlackList(self._base, self._bodies[f'link_{leg}_2'])
        self._foot_leg = {f'link_{leg}_3': leg - 1 for leg in range(1, N_LEGS + 1)}
        self._dofs = [self.skel.getDof(name) for name in self.model.joint_names]
        self._dof_index = np.array([dof.getIndexInSkeleton() for dof in self._dofs])
        effort = np.array([lim.effort for lim in self.model.limits])
        self._effort_whole = effort
        self._kp_whole = np.array([servo_kp(e, self.settings.compliance_slope) for e in effort])
        self._damping_whole = np.array(
            [
                lim.effort / lim.velocity if self.settings.back_emf else 0.0
                for lim in self.model.limits
            ]
        )
        # DART takes the smaller of two surfaces' coefficients: both at SimConfig.friction
        for body in self._bodies.values():
            for k in range(body.getNumShapeNodes()):
                node = body.getShapeNode(k)
                if node.hasDynamicsAspect():
                    node.getDynamicsAspect().setFrictionCoeff(self.config.friction)
        ground_shape.getDynamicsAspect().setFrictionCoeff(self.config.friction)
        self._tibias = [self._bodies[f'link_{leg}_3'] for leg in range(1, N_LEGS + 1)]
        self._tibia_whole = [self._tibia_parts(body) for body in self._tibias]
        # copies of the whole tibias' mass, centre of mass and moment (getInertia is a view)
        self._tibia_inertia = [
            (
                float(body.getMass()),
                np.array(body.getLocalCOM(), dtype=float),
                np.array(body.getInertia().getMoment(), dtype=float),
            )
            for body in self._tibias
        ]
        self._shape_of: list[float] = [1.0] * N_LEGS  # the tibia length fraction each leg has
        self._lost: list[bool] = [False] * N_LEGS
        self._failed_pairs: list[tuple[Any, Any]] = []
        self._target = np.zeros(3 * N_LEGS)
        self._kp = self._kp_whole.copy()
        self._effort = self._effort_whole.copy()
        self._torque = np.zeros(3 * N_LEGS)
        self._forces = np.zeros(self.skel.getNumDofs())  # the free joint's stay 0
        self._motors_on = True
        self._blown_up_at: float | None = None
        for name, dof in zip(self.model.joint_names, self._dofs):
            # The URDF's position limits are enforced as in the other engines. DART would also
            # enforce its velocity limit as a hard constraint: the servo's speed limit is its
            # back-EMF (the no-load speed), as in MuJoCo, so that constraint is lifted.
            self.skel.getJoint(name).setLimitEnforcement(True)
            dof.setVelocityLimits(-_NO_LIMIT, _NO_LIMIT)
        self._apply_failed_legs()
        self.reset(np.zeros(3 * N_LEGS))

    # -- damage ------------------------------------------------------------------------------
    def _tibia_parts(self, body: Any) -> tuple[TibiaShape, list[tuple[Any, np.ndarray, Any]]]:
        """Return the whole tibia's shape and its shape nodes (node, offset, box size or None)."""
        parts, box, foot = [], None, None
        for k in range(body.getNumShapeNodes()):
            node = body.getShapeNode(k)
            shape = node.getShape()
            offset = np.array(node.getRelativeTranslation(), dtype=float)
            if isinstance(shape, dart.dynamics.BoxShape):
                size = np.array(shape.getSize(), dtype=float)
                parts.append((node, offset, size))
                box = (offset, size)
            else:
                parts.append((node, offset, None))
                foot = (offset, float(shape.getRadius()))
        if box is None or foot is None:
            raise RuntimeError(f'{body.getName()} has no box and sphere to shape')
        whole = TibiaShape(
            box_lo=box[0][0] - box[1][0] / 2,
            box_hi=box[0][0] + box[1][0] / 2,
            foot_x=foot[0][0],
            foot_radius=foot[1],
            mass=body.getMass(),
            com_x=float(np.asarray(body.getLocalCOM())[0]),
        )
        return whole, parts

    def _shape_tibia(self, leg: int, fraction: float, lost: bool) -> None:
        """Give ``leg``'s tibia its shape (cut to ``fraction``), mass and collisions."""
        i = leg - 1
        if (self._shape_of[i], self._lost[i]) == (fraction, lost):
            return
        body = self._tibias[i]
        whole, parts = self._tibia_whole[i]
        shape = whole.shortened(fraction) if fraction != 1.0 else whole
        for node, offset, size in parts:  # the whole tibia's numbers exactly when not cut
            pos = offset.copy()
            if size is None:
                pos[0] = shape.foot_x if fraction != 1.0 else offset[0]
            else:
                cut = size.copy()
                if fraction != 1.0:
                    cut[0] = shape.box_hi - shape.box_lo
                    pos[0] = (shape.box_hi + shape.box_lo) / 2
                node.getShape().setSize(cut)
            node.setRelativeTranslation(pos)
        mass, com, moment = self._tibia_inertia[i]
        scale = LOST_TIBIA_MASS / whole.mass if lost else fraction
        if scale != 1.0:
            com = com.copy()
            com[0] = shape.com_x
        body.setInertia(dart.dynamics.Inertia(mass * scale, com, moment * scale))
        body.setCollidable(not lost)
        self._shape_of[i], self._lost[i] = fraction, lost

    def _apply_failed_legs(self) -> None:
        damage = self.damage
        for a, b in self._failed_pairs:
            self._filter.removeBodyNodePairFromBlackList(a, b)
        self._failed_pairs = []
        self._kp = self._kp_whole.copy()
        self._effort = self._effort_whole.copy()
        for leg in range(1, N_LEGS + 1):
            kind = damage.kind_of(leg)
            if kind in ('lifted', 'unpowered'):
                # In the folded failure pose the tibia overlaps its own coxa (the real servo
                # clamps near -150 deg there): that one pair does not collide while failed.
                pair = (self._bodies[f'link_{leg}_1'], self._bodies[f'link_{leg}_3'])
                self._filter.addBodyNodePairToBlackList(*pair)
                self._failed_pairs.append(pair)
            fraction = damage.tibia_fraction(leg) if kind == 'shortened' else 1.0
            self._shape_tibia(leg, fraction, kind == 'no_tibia')
            strength = damage.strength_of(leg)
            for slot in range(3 * (leg - 1), 3 * leg):
                self._kp[slot] *= strength
                self._effort[slot] *= strength
                self._dofs[slot].setDampingCoefficient(float(self._damping_whole[slot]))
                self._dofs[slot].setCoulombFriction(0.0)
        for slot in damage.dead_slots():  # no torque: the back-driven gearbox's friction only
            self._kp[slot] = self._effort[slot] = 0.0
            self._dofs[slot].setDampingCoefficient(0.0)
            self._dofs[slot].setCoulombFriction(DEAD_SERVO_FRICTION)
        if self._held_slots.size:
            self._target[self._held_slots] = self._held_values

    def _reset_state(self, q: np.ndarray, body_height: float) -> None:
        positions = np.zeros(self.skel.getNumDofs())
        positions[5] = body_height  # free joint: rotation vector (3), then translation (3)
        positions[self._dof_index] = q
        self.skel.setPositions(positions)
        self.skel.setVelocities(np.zeros(self.skel.getNumDofs()))
        self.skel.resetAccelerations()
        self.skel.clearExternalForces()
        self.skel.clearConstraintImpulses()
        self.world.setTime(0.0)
        self._target = q.copy()
        self._blown_up_at = None

    # -- commands and steps --------------------------------------------------------------------
    def prepare_rows(self, positions: np.ndarray, velocities: np.ndarray) -> np.ndarray:
        # ``velocities`` go unused: the RX firmware has no velocity feed-forward
        return self._position_targets(positions)

    def apply_row(self, rows: Any, index: int) -> None:
        self._target = rows[index]

    def set_motor_power(self, on: bool) -> None:
        self._motors_on = bool(on)

    def step(self) -> StepReport:
        skel, index, forces = self.skel, self._dof_index, self._forces
        for _ in range(self._substeps):  # the servo torque from the state each substep starts at
            if self._motors_on:
                q = skel.getPositions()[index]
                self._torque = np.clip(self._kp * (self._target - q), -self._effort, self._effort)
            else:
                self._torque = np.zeros(3 * N_LEGS)
            forces[index] = self._torque
            skel.setForces(forces)
            self.world.step()
        self.time += self.dt
        report = self._read_contacts()
        report.unstable = False
        if self._blown_up_at is None and not np.isfinite(self.skel.getPositions()).all():
            self._blown_up_at = self.time
            report.unstable = True
        return report

    def _read_contacts(self) -> StepReport:
        r = self.report
        r.contacts = [False] * N_LEGS
        r.body_ground = None
        r.self_collision = None
        ground, foot_leg = self._ground_name, self._foot_leg
        for contact in self.world.getLastCollisionResult().getContacts():
            a = contact.collisionObject1.getShapeFrame().asShapeNode().getBodyNodePtr().getName()
            b = contact.collisionObject2.getShapeFrame().asShapeNode().getBodyNodePtr().getName()
            if a == ground or b == ground:
                link = b if a == ground else a
                leg = foot_leg.get(link)
                if leg is not None:
                    r.contacts[leg] = True
                elif r.body_ground is None:
                    r.body_ground = link
            elif r.self_collision is None:
                r.self_collision = f'{a} / {b}'
        return r

    def rollout(
        self,
        tables: Sequence[JointRows],
        n_steps: int,
        stop_on_collision: bool = False,
        record_contacts: bool = False,
        record_tilt: bool = False,
    ) -> list[PlayResult]:
        results = []
        for table in tables:
            played = self._play(table, n_steps, stop_on_collision, record_contacts, record_tilt)
            if self._blown_up_at is not None:
                played = PlayResult(
                    played.steps,
                    np.zeros(N_LEGS, dtype=np.int64),
                    0,
                    None,
                    np.full(3, np.nan),
                    unstable=f'the DART physics became unstable at t = {self._blown_up_at:.3f} s',
                )
            results.append(played)
        return results

    # -- readings -------------------------------------------------------------------------------
    def base_pose(self) -> tuple[np.ndarray, np.ndarray]:
        t = self._base.getWorldTransform()
        return np.array(t.translation(), dtype=float), matrix_to_quat(np.asarray(t.rotation()))

    def base_velocity(self) -> tuple[np.ndarray, np.ndarray]:
        return (
            np.array(self._base.getLinearVelocity(), dtype=float),
            np.array(self._base.getAngularVelocity(), dtype=float),
        )

    def link_poses(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        poses = {}
        for name, body in self._bodies.items():
            t = body.getWorldTransform()
            poses[name] = (
                np.array(t.translation(), dtype=float),
                matrix_to_quat(np.asarray(t.rotation())),
            )
        return poses

    def link_masses(self) -> dict[str, float]:
        return {name: float(body.getMass()) for name, body in self._bodies.items()}

    def joint_states(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return (
            np.asarray(self.skel.getPositions(), dtype=float)[self._dof_index],
            np.asarray(self.skel.getVelocities(), dtype=float)[self._dof_index],
            self._torque.copy(),
        )

    def render(
        self,
        width: int = 480,
        height: int = 360,
        distance: float = 0.9,
        yaw: float = 30.0,
        pitch: float = -25.0,
    ) -> np.ndarray:
        raise RuntimeError(
            'the DART engine does not render (dartpy renders only in an OpenSceneGraph window); '
            'render with --engine pybullet or --engine mujoco'
        )

    def close(self) -> None:
        world = getattr(self, 'world', None)
        if world is not None:
            world.removeAllSkeletons()
            self.world = None
