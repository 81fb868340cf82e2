# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The MuJoCo engine: the fast engine for map generation and large experiments.

The model is built at load time from hexapod_description's URDF with ``MjSpec``, so geometry,
masses, inertias, joint limits and the effort and velocity limits have one source of truth.
The URDF importer makes the root link the world; a ``floating`` joint from a massless root link
is added to the URDF text first, so ``base_link`` keeps its inertia and moves freely. The
massless foot frames are fused into the tibias, as in PyBullet.

What every step must know (foot contacts, a non-foot link on the ground, self-collision) is
measured by eight MuJoCo ``contact`` sensors (one per foot, the whole robot on the floor, the
robot on itself; a non-foot link is on the ground when the robot has more floor contacts than its
feet), so :meth:`MujocoSimulator.rollout` lets C run all the
steps of a batch of gaits (``mujoco.rollout``) with no Python per step. When collisions are
fatal (map generation) it plays each gait in chunks and stops after the chunk of its first
collision: the same steps bit for bit, without the rest of a gait that is already invalid.

Servos (Dynamixel RX-28 on coxa and tibia, RX-64 on femur; see :class:`MujocoSettings`):
torque = clip(kp (q_target - q), -effort, effort) - (effort / velocity) q_dot, i.e. a
proportional position servo saturating at the URDF effort limit, plus the motor's back-EMF,
which makes the URDF velocity limit the no-load speed. The RX firmware has no velocity
feed-forward, so the table's velocities are not used by this engine.

A physics variant (:mod:`hexapod_sim.variants`) scales the servos' stall torque and no-load
speed and the links' masses and inertias when the model is built, and delays every command by
``latency_rows`` rows (the first rows hold the pose of the reset), stepping one at a time and in
a rollout alike.
"""

from __future__ import annotations

from collections import deque
from typing import Any, Sequence
import xml.etree.ElementTree as ET

from hexapod_description import N_LEGS
from hexapod_sim.damage import DEAD_SERVO_ARMATURE, DEAD_SERVO_FRICTION, LOST_TIBIA_MASS
from hexapod_sim.engine_settings import MujocoSettings
from hexapod_sim.shortened import TibiaShape
from hexapod_sim.simulator import (
    JointRows,
    peak_tilt,
    PlayResult,
    SimConfig,
    Simulator,
    StepReport,
)
import mujoco
from mujoco import rollout as mj_rollout
import numpy as np

INTEGRATORS = {
    'implicitfast': mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
    'implicit': mujoco.mjtIntegrator.mjINT_IMPLICIT,
    'euler': mujoco.mjtIntegrator.mjINT_EULER,
}
CONES = {'pyramidal': mujoco.mjtCone.mjCONE_PYRAMIDAL, 'elliptic': mujoco.mjtCone.mjCONE_ELLIPTIC}
SOLVERS = {
    'newton': mujoco.mjtSolver.mjSOL_NEWTON,
    'cg': mujoco.mjtSolver.mjSOL_CG,
    'pgs': mujoco.mjtSolver.mjSOL_PGS,
}


#: Steps per chunk of a rollout that stops at its first collision (stop_on_collision): a first
#: short one (0.1 s at 240 Hz: many map proposals collide on their first steps), then 0.5 s
#: each. A gait that collides plays at most one chunk past the collision; a gait that does not
#: pays a rollout call per chunk (about 2 % more than one call, measured).
COLLISION_CHUNKS = (24, 120)

# Collision bits. Every geom collides with every other (contype 1, conaffinity all) unless a
# leg is failed: then its coxa and tibia get their own bits, which each other's affinity lacks.
_ALL = 0x7FFFFFFF


def _urdf_with_free_base(path: str) -> str:
    root = ET.parse(path).getroot()
    ET.SubElement(root, 'link', name='hexapod_world_root')
    joint = ET.SubElement(root, 'joint', name='base_free', type='floating')
    ET.SubElement(joint, 'parent', link='hexapod_world_root')
    ET.SubElement(joint, 'child', link='base_link')
    return ET.tostring(root, encoding='unicode')


class MujocoSimulator(Simulator):
    """The hexapod in MuJoCo."""

    engine = 'mujoco'

    def __init__(self, config: SimConfig | None = None):
        super().__init__(config)
        self.settings: MujocoSettings
        self.m = self._build_model()
        self.d = mujoco.MjData(self.m)
        m = self.m
        self._qadr = np.array([m.jnt_qposadr[m.joint(name).id] for name in self.model.joint_names])
        self._dadr = np.array([m.jnt_dofadr[m.joint(name).id] for name in self.model.joint_names])
        self._act = np.array([m.actuator(name).id for name in self.model.joint_names])
        sensor = {m.sensor(i).name: int(m.sensor_adr[i]) for i in range(m.nsensor)}
        self._foot_adr = np.array([sensor[f'foot_{leg}'] for leg in range(1, N_LEGS + 1)])
        self._ground_links = [name for name in self._link_bodies() if not name.endswith('_3')]
        self._ground_bodies = [m.body(name).id for name in self._ground_links]
        self._floor_adr = sensor['robot_on_floor']
        self._floor = m.geom('floor').id
        self._self_adr = sensor['self_collision']
        self._coxa_geoms = [self._geoms_of(f'link_{leg}_1') for leg in range(1, N_LEGS + 1)]
        self._tibia_geoms = [self._geoms_of(f'link_{leg}_3') for leg in range(1, N_LEGS + 1)]
        # the healthy values damage scales (weak servos, a lost tibia)
        self._tibia_bodies = [m.body(f'link_{leg}_3').id for leg in range(1, N_LEGS + 1)]
        self._tibia_mass = m.body_mass[self._tibia_bodies].copy()
        self._tibia_inertia = m.body_inertia[self._tibia_bodies].copy()
        self._kp = m.actuator_gainprm[self._act, 0].copy()
        self._effort = m.actuator_forcerange[self._act, 1].copy()
        self._damping = m.dof_damping[self._dadr].copy()
        self._armature = m.dof_armature[self._dadr].copy()
        # each tibia's collision box and foot sphere, and the shape a shortened one scales
        self._tibia_box = [
            g[m.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX][0] for g in self._tibia_geoms
        ]
        self._tibia_foot = [
            g[m.geom_type[g] == mujoco.mjtGeom.mjGEOM_SPHERE][0] for g in self._tibia_geoms
        ]
        self._tibia_shape = [
            TibiaShape(
                box_lo=m.geom_pos[box, 0] - m.geom_size[box, 0],
                box_hi=m.geom_pos[box, 0] + m.geom_size[box, 0],
                foot_x=m.geom_pos[foot, 0],
                foot_radius=m.geom_size[foot, 0],
                mass=m.body_mass[body],
                com_x=m.body_ipos[body, 0],
            )
            for box, foot, body in zip(self._tibia_box, self._tibia_foot, self._tibia_bodies)
        ]
        self._tibia_com = m.body_ipos[self._tibia_bodies].copy()
        self._whole_geoms = [
            (
                m.geom_pos[b].copy(),
                m.geom_size[b].copy(),
                m.geom_aabb[b].copy(),
                m.geom_pos[f, 0],
                m.geom_rbound[b],
            )
            for b, f in zip(self._tibia_box, self._tibia_foot)
        ]
        self._state_spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        self._nstate = mujoco.mj_stateSize(m, self._state_spec)
        self._renderer: Any = None
        self._late_rows: deque[np.ndarray] = deque()  # commands not yet reached the servos
        self._apply_failed_legs()
        self.reset(np.zeros(3 * N_LEGS))

    # -- the model -------------------------------------------------------------------------------
    def _link_bodies(self) -> list[str]:
        return ['base_link'] + [
            f'link_{leg}_{k}' for leg in range(1, N_LEGS + 1) for k in (1, 2, 3)
        ]

    def _geoms_of(self, body: str) -> np.ndarray:
        return np.flatnonzero(self.m.geom_bodyid == self.m.body(body).id)

    def _build_model(self) -> mujoco.MjModel:
        s, cfg = self.settings, self.config
        spec = mujoco.MjSpec.from_string(_urdf_with_free_base(str(self.model.path)))
        spec.option.timestep = s.time_step / s.substeps
        spec.option.integrator = INTEGRATORS[s.integrator]
        spec.option.solver = SOLVERS[s.solver]
        spec.option.cone = CONES[s.cone]
        spec.option.iterations = s.iterations
        spec.option.tolerance = s.tolerance
        spec.option.gravity = [0.0, 0.0, -9.81]
        friction = [cfg.friction, s.torsional_friction, s.rolling_friction]
        spec.worldbody.add_geom(
            name='floor',
            type=mujoco.mjtGeom.mjGEOM_PLANE,
            size=[0.0, 0.0, 1.0],
            rgba=[0.82, 0.84, 0.86, 1.0],
        )
        # for rendered frames only (lights take no part in the physics)
        spec.worldbody.add_light(
            name='sun',
            pos=[0.0, 0.0, 3.0],
            dir=[0.0, 0.0, -1.0],
            type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL,
            diffuse=[0.8, 0.8, 0.8],
        )
        for geom in spec.geoms:  # MuJoCo takes the larger of two geoms' coefficients: all equal
            geom.friction = friction
            # no friction at all is a 1-D (normal-only) contact: a zero-width pyramid is singular
            geom.condim = 3 if cfg.friction > 0 else 1
            geom.contype, geom.conaffinity = 1, _ALL
            geom.solref = [s.contact_timeconst, s.contact_dampratio]
        # Section 3.5.3: the femurs would hit the base before their joint limits.
        for leg in range(1, N_LEGS + 1):
            spec.add_exclude(bodyname1='base_link', bodyname2=f'link_{leg}_2')
        for lim in self.model.limits:
            joint = spec.joint(lim.name)
            effort, velocity = lim.effort * s.effort_scale, lim.velocity * s.speed_scale
            joint.damping = [effort / velocity if s.back_emf else 0.0, 0.0, 0.0]
            joint.armature = s.armature
            kp = s.servo_kp(effort)
            act = spec.add_actuator(
                name=lim.name, target=lim.name, trntype=mujoco.mjtTrn.mjTRN_JOINT
            )
            act.gaintype, act.biastype = mujoco.mjtGain.mjGAIN_FIXED, mujoco.mjtBias.mjBIAS_AFFINE
            act.gainprm[0] = kp
            act.biasprm[0], act.biasprm[1], act.biasprm[2] = 0.0, -kp, 0.0
            act.forcelimited = True
            act.forcerange = [-effort, effort]

        def contact_sensor(name: str, obj: tuple, ref: tuple) -> None:
            sensor = spec.add_sensor(
                name=name,
                type=mujoco.mjtSensor.mjSENS_CONTACT,
                objtype=obj[0],
                objname=obj[1],
                reftype=ref[0],
                refname=ref[1],
            )
            sensor.intprm[0] = 1  # data: "found", the number of matching contacts
            sensor.intprm[1] = 0  # no reduction
            sensor.intprm[2] = 1  # one slot

        # Eight sensors, not one per link: each scans every contact at every physics step, and
        # 20 of them took a quarter of a step's time (docs/simulator.md, "Cheaper converged").
        floor = (mujoco.mjtObj.mjOBJ_GEOM, 'floor')
        for leg in range(1, N_LEGS + 1):
            contact_sensor(f'foot_{leg}', (mujoco.mjtObj.mjOBJ_BODY, f'link_{leg}_3'), floor)
        robot = (mujoco.mjtObj.mjOBJ_XBODY, 'base_link')  # subtree: the whole robot
        contact_sensor('robot_on_floor', robot, floor)
        contact_sensor('self_collision', robot, robot)
        return self._scale_masses(spec.compile())

    def _scale_masses(self, m: mujoco.MjModel) -> mujoco.MjModel:
        """Scale each link type's mass and inertia by the settings' factors."""
        s = self.settings
        scales = {'1': s.coxa_mass_scale, '2': s.femur_mass_scale, '3': s.tibia_mass_scale}
        changed = False
        for name in self._link_bodies():
            scale = s.base_mass_scale if name == 'base_link' else scales[name[-1]]
            if scale != 1.0:
                body = m.body(name).id
                m.body_mass[body] *= scale
                m.body_inertia[body] *= scale
                changed = True
        if changed:  # the derived constants (subtree masses, ...) follow
            mujoco.mj_setConst(m, mujoco.MjData(m))
        return m

    # -- configuration ---------------------------------------------------------------------
    def _apply_failed_legs(self) -> None:
        m, damage = self.m, self.damage
        masses_changed = False
        for leg in range(1, N_LEGS + 1):
            coxa, tibia = self._coxa_geoms[leg - 1], self._tibia_geoms[leg - 1]
            kind = damage.kind_of(leg)
            m.geom_contype[coxa] = m.geom_contype[tibia] = 1
            m.geom_conaffinity[coxa] = m.geom_conaffinity[tibia] = _ALL
            if kind in ('lifted', 'unpowered'):
                # In the folded failure pose the tibia overlaps its own coxa (the real servo
                # clamps near -150 deg there): that one pair does not collide while failed.
                m.geom_contype[coxa], m.geom_conaffinity[coxa] = 1 << leg, _ALL & ~(1 << (leg + 8))
                m.geom_contype[tibia], m.geom_conaffinity[tibia] = (
                    1 << (leg + 8),
                    _ALL & ~(1 << leg),
                )
            elif kind == 'no_tibia':  # it touches nothing
                m.geom_contype[tibia] = m.geom_conaffinity[tibia] = 0
            masses_changed |= self._shape_tibia(leg, kind)
            strength = damage.strength_of(leg)
            for slot in range(3 * (leg - 1), 3 * leg):
                act = self._act[slot]
                kp, effort = self._kp[slot] * strength, self._effort[slot] * strength
                m.actuator_gainprm[act, 0] = kp
                m.actuator_biasprm[act, 1] = -kp
                m.actuator_forcerange[act] = [-effort, effort]
                dof = self._dadr[slot]
                masses_changed |= bool(m.dof_armature[dof] != self._armature[slot])
                m.dof_damping[dof], m.dof_armature[dof] = self._damping[slot], self._armature[slot]
                m.dof_frictionloss[dof] = 0.0
        for slot in damage.dead_slots():  # no torque: the back-driven gearbox's friction only
            act, dof = self._act[slot], self._dadr[slot]
            m.actuator_gainprm[act, 0] = m.actuator_biasprm[act, 1] = 0.0
            m.actuator_forcerange[act] = [0.0, 0.0]
            m.dof_damping[dof], m.dof_armature[dof] = 0.0, DEAD_SERVO_ARMATURE
            m.dof_frictionloss[dof] = DEAD_SERVO_FRICTION
            masses_changed = True  # the armature enters the constants
        if masses_changed:  # the derived constants follow (on scratch data: the state stays)
            mujoco.mj_setConst(m, mujoco.MjData(m))
        # the broad phase filters body pairs by the OR of their geoms' masks, which MuJoCo derives
        # only when compiling (and in mj_setConst): without this a damage's masks outlived it
        _sync_body_masks(m)
        if self._held_slots.size:
            self.d.ctrl[self._act[self._held_slots]] = self._held_values

    def _shape_tibia(self, leg: int, kind: str | None) -> bool:
        """Give ``leg``'s tibia its mass and shape (lost, shortened or whole); True if changed."""
        m, i = self.m, leg - 1
        body, box, foot = self._tibia_bodies[i], self._tibia_box[i], self._tibia_foot[i]
        whole = self._tibia_shape[i]
        fraction = self.damage.tibia_fraction(leg) if kind == 'shortened' else 1.0
        scale = LOST_TIBIA_MASS / whole.mass if kind == 'no_tibia' else fraction
        if (m.body_mass[body], m.geom_pos[foot, 0]) == (
            self._tibia_mass[i] * scale,
            self._whole_geoms[i][3] if fraction == 1.0 else whole.shortened(fraction).foot_x,
        ):
            return False
        m.body_mass[body] = self._tibia_mass[i] * scale
        m.body_inertia[body] = self._tibia_inertia[i] * scale
        box_pos, box_size, box_aabb, foot_x, rbound = self._whole_geoms[i]
        m.body_ipos[body] = self._tibia_com[i]
        m.geom_pos[box], m.geom_size[box], m.geom_aabb[box] = box_pos, box_size, box_aabb
        m.geom_pos[foot, 0], m.geom_rbound[box] = foot_x, rbound
        if fraction != 1.0:
            shape = whole.shortened(fraction)
            half = (shape.box_hi - shape.box_lo) / 2
            m.body_ipos[body, 0] = shape.com_x
            m.geom_size[box, 0] = m.geom_aabb[box, 3] = half
            m.geom_pos[box, 0] = (shape.box_hi + shape.box_lo) / 2
            m.geom_pos[foot, 0] = shape.foot_x
            m.geom_rbound[box] = float(np.linalg.norm(m.geom_size[box]))
        return True

    def _reset_state(self, q: np.ndarray, body_height: float) -> None:
        m, d = self.m, self.d
        # zeroes velocities, warm start and time: bit for bit a fresh start
        mujoco.mj_resetData(m, d)
        d.qpos[:7] = [0.0, 0.0, body_height, 1.0, 0.0, 0.0, 0.0]
        d.qpos[self._qadr] = q
        d.ctrl[self._act] = q
        self._late_rows.clear()
        mujoco.mj_forward(m, d)

    def prepare_rows(self, positions: np.ndarray, velocities: np.ndarray) -> np.ndarray:
        return self._position_targets(positions)

    def apply_row(self, rows: Any, index: int) -> None:
        latency = self.settings.latency_rows
        if not latency:
            self.d.ctrl[self._act] = rows[index]
            return
        # the servos get the row sent latency rows ago (until then, what they hold)
        self._late_rows.append(np.array(rows[index]))
        if len(self._late_rows) > latency:
            self.d.ctrl[self._act] = self._late_rows.popleft()

    def set_motor_power(self, on: bool) -> None:
        if on:
            self.m.opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_ACTUATION)
        else:
            self.m.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_ACTUATION)

    def step(self) -> StepReport:
        warnings = self.d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number
        sensors = None
        ground = pair = None
        for _ in range(self.settings.substeps):
            # sensors and d.contact: the state this physics step started from
            mujoco.mj_step(self.m, self.d)
            now = self.d.sensordata
            # a contact in any of the row's physics steps counts (as rollout counts it), named
            # from the contacts of the physics step that found it
            if ground is None and self._on_ground(now):
                ground = self._ground_link()
            if pair is None and now[self._self_adr] > 0:
                pair = self._self_collision_pair()
            sensors = now.copy() if sensors is None else np.maximum(sensors, now)
        self.time += self.dt
        report = self.report
        report.contacts = (sensors[self._foot_adr] > 0).tolist()
        report.body_ground, report.self_collision = ground, pair
        # MuJoCo resets the data after a blow-up and carries on: say so
        report.unstable = self.d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > warnings
        return report

    def _on_ground(self, sensordata: np.ndarray) -> np.ndarray:
        """Whether a non-foot link touches the floor: more robot-floor contacts than feet's."""
        feet = sensordata[..., self._foot_adr].sum(axis=-1)
        return sensordata[..., self._floor_adr] > feet

    def _collided(self, sensordata: np.ndarray) -> np.ndarray:
        """Return per physics step (row of ``sensordata``): a link on the floor, or robot-robot."""
        return self._on_ground(sensordata) | (sensordata[..., self._self_adr] > 0)

    def _report(self, sensordata: np.ndarray) -> StepReport:
        """Report the physics step whose contacts ``d.contact`` holds now."""
        r = self.report
        r.contacts = (sensordata[self._foot_adr] > 0).tolist()
        r.body_ground = self._ground_link() if self._on_ground(sensordata) else None
        r.self_collision = self._self_collision_pair() if sensordata[self._self_adr] > 0 else None
        return r

    def _ground_link(self) -> str:
        """Name the first non-foot link (base, coxae, femurs) on the floor in ``d.contact``."""
        m, d = self.m, self.d
        on_floor = {
            int(m.geom_bodyid[g1 if g2 == self._floor else g2])
            for g1, g2 in zip(d.contact.geom1[: d.ncon], d.contact.geom2[: d.ncon])
            if self._floor in (g1, g2)
        }
        for name, body in zip(self._ground_links, self._ground_bodies):
            if body in on_floor:
                return name
        return 'a link'  # the sensor saw it; d.contact is of another step (not expected)

    def _self_collision_pair(self) -> str:
        """Name 'link_a / link_b' of the first robot-robot contact in ``d.contact``."""
        m, d = self.m, self.d
        for i in range(d.ncon):
            b1, b2 = m.geom_bodyid[d.contact.geom1[i]], m.geom_bodyid[d.contact.geom2[i]]
            if b1 != 0 and b2 != 0:
                return f'{m.body(b1).name} / {m.body(b2).name}'
        return 'between robot links'

    # -- the native batch ------------------------------------------------------------------
    def rollout(
        self,
        tables: Sequence[JointRows],
        n_steps: int,
        stop_on_collision: bool = False,
        record_contacts: bool = False,
        record_tilt: bool = False,
    ) -> list[PlayResult]:
        if not tables:
            return []
        m, d = self.m, self.d
        n = len(tables)
        sub = self.settings.substeps  # physics steps per row, the row's target held through them
        initial = np.empty((n, self._nstate))
        control = np.empty((n, n_steps * sub, m.nu))
        # each row reaches the servos latency_rows late; until then they hold the reset's pose
        steps = np.maximum(np.arange(n_steps) - self.settings.latency_rows, 0)
        for i, table in enumerate(tables):
            rows = self.prepare_rows(table.positions, table.velocities)
            self.reset(table.positions[0])
            mujoco.mj_getState(m, d, initial[i], self._state_spec)
            control[i][:, self._act] = np.repeat(rows[steps % len(rows)], sub, axis=0)
        if stop_on_collision:
            # each gait in chunks, up to the chunk of its first collision: a gait that collides
            # early (a map proposal, often) costs a few chunks, not all its steps
            runs = [self._rollout_until_collision(initial[i], control[i]) for i in range(n)]
            fine_state = [r[0] for r in runs]
            fine_sd = [r[1] for r in runs]
        else:
            full_state, full_sd = mj_rollout.rollout(
                m, d, initial, control, initial_warmstart=np.zeros((n, m.nv))
            )
            fine_state, fine_sd = list(full_state), list(full_sd)
        # per row: the state at its end; a sensor's largest reading over its physics steps
        ends = slice(sub - 1, None, sub)
        state = [x[ends] for x in fine_state]
        sensordata = [x.reshape(-1, sub, x.shape[-1]).max(axis=1) for x in fine_sd]
        unstable = {}  # {rollout: the row of its first bad physics step}
        for i in range(n):
            bad = self._unstable_steps(initial[i][None], fine_state[i][None])
            # collisions fatal: a collision before the blow-up ends the gait first
            if bad and not (stop_on_collision and self._collided(fine_sd[i][: bad[0]]).any()):
                unstable[i] = bad[0] // sub
        results = [
            self._unstable_result(unstable[i])
            if i in unstable
            else self._result(
                initial[i],
                fine_state[i],
                fine_sd[i],
                state[i],
                sensordata[i],
                n_steps,
                stop_on_collision,
                record_contacts,
                record_tilt,
            )
            for i in range(n)
        ]
        # leave the simulator in the final state of the last table
        mujoco.mj_setState(m, d, state[n - 1][results[-1].steps - 1], self._state_spec)
        mujoco.mj_forward(m, d)
        self.time = results[-1].steps * self.dt
        return results

    def _unstable_result(self, k: int) -> PlayResult:
        """Return the result of a rollout whose physics blew up in row ``k``."""
        return PlayResult(
            k + 1,
            np.zeros(N_LEGS, dtype=np.int64),
            0,
            None,
            np.full(3, np.nan),
            unstable=(
                f'the MuJoCo physics became unstable at t = {(k + 1) * self.dt:.3f} s '
                '(settings too stiff for the step)'
            ),
        )

    def _result(
        self,
        initial: np.ndarray,
        fine_state: np.ndarray,
        fine_sd: np.ndarray,
        state: np.ndarray,
        sd: np.ndarray,
        n_steps: int,
        stop_on_collision: bool,
        record_contacts: bool,
        record_tilt: bool,
    ) -> PlayResult:
        """
        Return one rollout's result from its states and sensors.

        ``fine_*`` per physics step, ``state`` and ``sd`` per row (a row's end state, its
        sensors' largest readings).
        """
        m, d, sub = self.m, self.d, self.settings.substeps
        feet = sd[:, self._foot_adr] > 0
        # a row collided if any of its physics steps did
        collided = self._collided(fine_sd).reshape(-1, sub).any(axis=1)
        hits = np.flatnonzero(collided)
        first = None
        used = n_steps
        if hits.size:
            k = int(hits[0])
            # its first physics step that collided (row k's); the contacts of a physics step
            # are those of the state it started from: recompute them
            in_row = self._collided(fine_sd[slice(k * sub, (k + 1) * sub)])
            j = k * sub + int(np.argmax(in_row))
            mujoco.mj_setState(m, d, initial if j == 0 else fine_state[j - 1], self._state_spec)
            mujoco.mj_forward(m, d)
            first = f'{self._report(fine_sd[j]).collision} at t = {(k + 1) * self.dt:.3f} s'
            if stop_on_collision:
                used = k + 1
        last = used - 1
        # a stop on a collision counts the feet of the steps before it (as the per-step loop)
        counts = feet[: last if stop_on_collision and hits.size else used].sum(axis=0)
        return PlayResult(
            used,
            counts.astype(np.int64),
            int(collided[:used].sum()),
            first,
            state[last, 1:4].copy(),
            feet[:used].copy() if record_contacts else None,
            # qpos[3:7] is (w, x, y, z)
            final_orientation=state[last, [5, 6, 7, 4]].copy(),
            # qpos[3:7] as (x, y, z, w)
            peak_tilt=peak_tilt(state[:used][:, [5, 6, 7, 4]]) if record_tilt else 0.0,
        )

    def _rollout_until_collision(
        self, initial: np.ndarray, control: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """
        One gait's states and sensor data, step by step, up to the chunk of its first collision.

        Each chunk (:data:`COLLISION_CHUNKS`) starts from the last one's final state and solver
        warm start, so the steps played are bit for bit those of one whole rollout (tested). A
        blow-up is found afterwards, as in a whole rollout (its first bad step is the same).
        """
        m, d = self.m, self.d
        n_steps = control.shape[0]
        state = np.empty((1, n_steps, self._nstate))
        sensors = np.empty((1, n_steps, m.nsensordata))
        start, warm = initial[None], np.zeros((1, m.nv))
        first, rest = (rows * self.settings.substeps for rows in COLLISION_CHUNKS)
        k0 = 0
        while k0 < n_steps:
            k1 = min(k0 + (first if k0 == 0 else rest), n_steps)
            mj_rollout.rollout(
                [m],  # lists: what the call takes when it skips its checks
                [d],
                start,
                control[None, k0:k1],
                initial_warmstart=warm,
                state=state[:, k0:k1],
                sensordata=sensors[:, k0:k1],
                nstep=k1 - k0,
                skip_checks=True,  # shapes and types made here
            )
            if self._collided(sensors[0, k0:k1]).any():
                return state[0, :k1], sensors[0, :k1]
            start, warm = state[:, k1 - 1], d.qacc_warmstart[None].copy()
            k0 = k1
        return state[0], sensors[0]

    def _unstable_steps(self, initial: np.ndarray, state: np.ndarray) -> dict[int, int]:
        """
        {rollout: first bad step} for the rollouts that blew up.

        On a numerical blow-up MuJoCo resets the data and carries on, so the simulated time
        (state[..., 0]) stops counting up from the start, or the state holds NaN; a per-rollout
        check of the trajectory itself.
        """
        h = self.m.opt.timestep  # a physics step: state holds one row per physics step
        steps = np.arange(1, state.shape[1] + 1) * h
        expected = initial[:, :1] + steps[None, :]
        bad = (np.abs(state[:, :, 0] - expected) > 0.5 * h) | ~np.isfinite(state).all(axis=2)
        return {int(i): int(np.argmax(bad[i])) for i in np.flatnonzero(bad.any(axis=1))}

    # -- readings --------------------------------------------------------------------------
    def base_pose(self) -> tuple[np.ndarray, np.ndarray]:
        qpos = self.d.qpos
        return qpos[0:3].copy(), np.array([qpos[4], qpos[5], qpos[6], qpos[3]])

    def base_velocity(self) -> tuple[np.ndarray, np.ndarray]:
        # free joint: linear velocity in the world frame, angular velocity in the body frame
        qvel = self.d.qvel
        return qvel[0:3].copy(), self.d.xmat[self.m.body('base_link').id].reshape(3, 3) @ qvel[3:6]

    def link_poses(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        m, d = self.m, self.d
        mujoco.mj_kinematics(m, d)
        poses = {}
        for name in self._link_bodies():
            body = m.body(name).id
            w, x, y, z = d.xquat[body]
            # MuJoCo bodies sit at link frames
            poses[name] = (
                d.xpos[body].copy(),
                np.array([x, y, z, w]),
            )
        return poses

    def link_masses(self) -> dict[str, float]:
        return {
            name: float(self.m.body_mass[self.m.body(name).id]) for name in self._link_bodies()
        }

    def joint_states(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        d = self.d
        return (
            d.qpos[self._qadr].copy(),
            d.qvel[self._dadr].copy(),
            d.actuator_force[self._act].copy(),
        )

    def render(
        self,
        width: int = 480,
        height: int = 360,
        distance: float = 0.9,
        yaw: float = 30.0,
        pitch: float = -25.0,
    ) -> np.ndarray:
        if self._renderer is None or (self._renderer.height, self._renderer.width) != (
            height,
            width,
        ):
            try:
                self._renderer = mujoco.Renderer(self.m, height=height, width=width)
            except Exception as exc:  # no OpenGL context (set MUJOCO_GL=egl or osmesa)
                raise RuntimeError(
                    f'MuJoCo cannot render here: {exc}. Set MUJOCO_GL=egl (GPU) or '
                    'MUJOCO_GL=osmesa (Debian: libosmesa6), or render with --engine pybullet'
                ) from exc
        camera = mujoco.MjvCamera()
        camera.lookat[:] = self.d.qpos[0:3]
        camera.distance, camera.azimuth, camera.elevation = distance, yaw, pitch
        self._renderer.update_scene(self.d, camera)
        return self._renderer.render().copy()

    def close(self) -> None:
        renderer = getattr(self, '_renderer', None)
        if renderer is not None:
            renderer.close()
            self._renderer = None


def _sync_body_masks(m: 'mujoco.MjModel') -> None:
    """Set each body's collision masks to the OR of its geoms' (as compiling does)."""
    contype = np.zeros(m.nbody, dtype=np.int64)
    conaffinity = np.zeros(m.nbody, dtype=np.int64)
    np.bitwise_or.at(contype, m.geom_bodyid, m.geom_contype.astype(np.int64))
    np.bitwise_or.at(conaffinity, m.geom_bodyid, m.geom_conaffinity.astype(np.int64))
    m.body_contype[:] = contype
    m.body_conaffinity[:] = conaffinity
