# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The engines' settings (ROS-free, and free of the engines themselves).

:class:`PyBulletSettings` and :class:`MujocoSettings` are plain, validated values: a
:class:`hexapod_sim.simulator.SimConfig` holds one, its fingerprint records it, and the engine
modules apply it. Keeping them here lets the simulator interface name its defaults without
importing an engine.
"""

from __future__ import annotations

from dataclasses import dataclass
import math


@dataclass(frozen=True)
class PyBulletSettings:
    """
    PyBullet settings.

    ``ACCURATE`` is PyBullet's default and the default everywhere. ``FAST`` trades solver
    iterations for speed; ``make bench-sim`` measured its ranking fidelity against ACCURATE below
    Spearman 0.95 (studies/engines/README.md), so nothing uses it unless asked to.
    """

    solver_iterations: int = 50
    time_step: float = 1.0 / 240.0
    cone_friction: bool = True
    #: PyBullet's default world also runs deformable-body machinery; the plain discrete
    #: multibody world skips it (no effect on rigid-body results).
    discrete_world: bool = False
    #: Solver stops iterating early once the squared residual is below this (PyBullet: 1e-7).
    residual_threshold: float = 1e-7
    #: 'rx': the servo model MuJoCo and DART share (MujocoSettings' docstring: the RX data
    #: sheet's compliance, stall torque and back-EMF), its torque computed at ``substeps`` per
    #: step. 'position': Bullet's position motor, as the thesis's simulator drove the joints (a
    #: velocity-level constraint up to the stall torque: about 25 times stiffer than the RX;
    #: studies/engines/README.md, "Where the engines differ", item 3).
    servo: str = 'rx'
    #: 'rx' only: physics steps per time step, the torque recomputed at each (960 Hz, as DART).
    substeps: int = 4
    #: 'rx' only: the RX factory compliance slope, as in MujocoSettings (kp 21.2 / 31.7 N m/rad).
    compliance_slope: float = 32.0

    def __post_init__(self) -> None:
        if self.solver_iterations < 1:
            raise ValueError(f'solver_iterations must be >= 1, got {self.solver_iterations}')
        if not 0 < self.time_step <= 0.01:
            raise ValueError(f'time_step must be in (0, 0.01] s, got {self.time_step}')
        if self.servo not in PYBULLET_SERVOS:
            raise ValueError(
                f'PyBullet setting servo must be one of {", ".join(PYBULLET_SERVOS)}, '
                f'got {self.servo!r}'
            )
        if isinstance(self.substeps, bool) or not isinstance(self.substeps, int):
            raise ValueError(
                f'PyBullet setting substeps must be an integer, got {self.substeps!r}'
            )
        if not 1 <= self.substeps <= 64:
            raise ValueError(f'PyBullet setting substeps must be in [1, 64], got {self.substeps}')
        if not (math.isfinite(self.compliance_slope) and 1.0 <= self.compliance_slope <= 256.0):
            raise ValueError(
                'PyBullet setting compliance_slope must be in [1, 256], '
                f'got {self.compliance_slope!r}'
            )


#: How PyBulletSettings.servo may drive the joints.
PYBULLET_SERVOS = ('position', 'rx')


ACCURATE = PyBulletSettings()
FAST = PyBulletSettings(solver_iterations=20)


#: Dynamixel RX position units: 1024 over 300 degrees (both RX-28 and RX-64).
DYNAMIXEL_RAD_PER_UNIT = math.radians(300.0) / 1024.0
#: The names each choice accepts (the engine maps them to MuJoCo's enums).
INTEGRATOR_NAMES = ('implicitfast', 'implicit', 'euler')
SOLVER_NAMES = ('newton', 'cg', 'pgs')
CONE_NAMES = ('pyramidal', 'elliptic')


def _in_range(name: str, value: float, low: float, high: float) -> None:
    if not (isinstance(value, (int, float)) and math.isfinite(value) and low <= value <= high):
        raise ValueError(f'MuJoCo setting {name} must be in [{low:g}, {high:g}], got {value!r}')


def _integer(name: str, value: int, low: int, high: int) -> None:
    if isinstance(value, bool) or not isinstance(value, int):
        raise ValueError(f'MuJoCo setting {name} must be an integer, got {value!r}')
    _in_range(name, value, low, high)


def _choice(name: str, value: str, options: tuple[str, ...]) -> None:
    if value not in options:
        raise ValueError(
            f'MuJoCo setting {name} must be one of {", ".join(options)}, got {value!r}'
        )


@dataclass(frozen=True)
class MujocoSettings:
    """
    Every engine-specific choice of the MuJoCo model, each with its reason.

    studies/engines/README.md shows how the results move when they change.
    """

    #: 240 Hz: the thesis's step, PyBullet's, and the rate of the gait tables (one row per step).
    time_step: float = 1.0 / 240.0
    #: Physics steps per time step (the row's target held through them), as PyBullet's and DART's.
    #: The servo's proportional term is explicit (implicitfast takes only the velocity terms
    #: implicitly) and a tibia's servo loop runs at about 240 rad/s, so one step per 240 Hz row
    #: has not converged on fast gaits: on the CMA-MAE map's 8 fastest and 8 random gaits their
    #: speeds moved by a median 0.129 m/s from 1 to 8 substeps (Spearman 0.29), by 0.009 from 4
    #: to 8 (0.96) (studies/engines, "Where the engines differ", item 6). 1 is kept as the
    #: default until the maps, ceilings and banks made at it are remade at 4.
    substeps: int = 1
    #: implicit in the servo damping and back-EMF terms: stiff servos stay stable at 240 Hz.
    integrator: str = 'implicitfast'
    #: Newton converges in a few iterations on this small model; 20 is a cap it rarely reaches.
    solver: str = 'newton'
    iterations: int = 20
    tolerance: float = 1e-8
    #: MuJoCo's default friction cone; elliptic gave the same ranking (Spearman within 0.03) at
    #: 1.6x the cost (studies/engines/README.md).
    cone: str = 'pyramidal'
    #: Dynamixel compliance slope in position units: the error over which the servo's torque
    #: ramps from 0 to its maximum. 32 is the RX-28/RX-64 factory default (the robot's firmware
    #: does not change it). kp = effort / (slope x 300 deg / 1024) = 21.2 (RX-28) and
    #: 31.7 N m/rad (RX-64) with the URDF's effort limits.
    compliance_slope: float = 32.0
    #: Back-EMF: damping = effort / velocity limit, so the servo's torque falls linearly to 0 at
    #: the URDF's no-load speed. Without it the soft servos oscillated and the model blew up.
    back_emf: bool = True
    #: Reflected rotor inertia [kg m^2]; the URDF has none and the RX data sheets give none.
    armature: float = 0.0
    #: Contact softness (MuJoCo's defaults): time constant 0.02 s (>= 2 time steps, MuJoCo's
    #: stability rule) and damping ratio 1; impedance 0.9..0.95 over 1 mm.
    contact_timeconst: float = 0.02
    contact_dampratio: float = 1.0
    #: Torsional and rolling friction of every contact (MuJoCo's defaults); sliding friction
    #: is the shared ``SimConfig.friction``.
    torsional_friction: float = 0.005
    rolling_friction: float = 0.0001
    #: A physics variant (hexapod_sim.variants, issue 66): the servos' stall torque and no-load
    #: speed as fractions of the URDF's, the rows of 240 Hz by which each command reaches the
    #: servos late, and each link type's mass and inertia as a fraction of the URDF's. At 1, 0
    #: and 1 (:data:`MUJOCO_VARIANT_DEFAULTS`) the model is the URDF's.
    effort_scale: float = 1.0
    speed_scale: float = 1.0
    latency_rows: int = 0
    base_mass_scale: float = 1.0
    coxa_mass_scale: float = 1.0
    femur_mass_scale: float = 1.0
    tibia_mass_scale: float = 1.0

    def __post_init__(self) -> None:
        _integer('latency_rows', self.latency_rows, 0, 48)
        for name in MUJOCO_VARIANT_DEFAULTS:
            if name != 'latency_rows':
                _in_range(name, getattr(self, name), 0.1, 10.0)
        _in_range('time_step', self.time_step, 1e-4, 0.01)
        _integer('substeps', self.substeps, 1, 64)
        _choice('integrator', self.integrator, INTEGRATOR_NAMES)
        _choice('solver', self.solver, SOLVER_NAMES)
        _choice('cone', self.cone, CONE_NAMES)
        _integer('iterations', self.iterations, 1, 1000)
        _in_range('tolerance', self.tolerance, 0.0, 1e-2)
        _in_range('compliance_slope', self.compliance_slope, 1.0, 256.0)
        _in_range('armature', self.armature, 0.0, 1.0)
        _in_range('contact_timeconst', self.contact_timeconst, 2 * self.time_step, 1.0)
        _in_range('contact_dampratio', self.contact_dampratio, 0.1, 10.0)
        _in_range('torsional_friction', self.torsional_friction, 0.0, 1.0)
        _in_range('rolling_friction', self.rolling_friction, 0.0, 1.0)

    def servo_kp(self, effort: float) -> float:
        """Proportional gain [N m/rad] of a servo with this stall torque [N m]."""
        return servo_kp(effort, self.compliance_slope)


def servo_kp(effort: float, compliance_slope: float) -> float:
    """
    Proportional gain [N m/rad] of a Dynamixel RX servo with this stall torque [N m].

    The compliance slope (position units) is the error over which the torque ramps from 0 to
    its maximum, so kp = effort / (slope x 300 deg / 1024). One formula for every engine.
    """
    return effort / (compliance_slope * DYNAMIXEL_RAD_PER_UNIT)


#: The variant fields (added after maps were made) at the model's own values: a fingerprint
#: leaves them out there, so a map made before them keeps its fingerprint.
MUJOCO_VARIANT_DEFAULTS = {
    'effort_scale': 1.0,
    'speed_scale': 1.0,
    'latency_rows': 0,
    'base_mass_scale': 1.0,
    'coxa_mass_scale': 1.0,
    'femur_mass_scale': 1.0,
    'tibia_mass_scale': 1.0,
}

DEFAULT_SETTINGS = MujocoSettings()

#: The collision detectors DART can use (its own narrow phase for boxes and spheres only).
DART_COLLISION_DETECTORS = ('ode', 'bullet', 'fcl')


@dataclass(frozen=True)
class DartSettings:
    """
    DART settings: the judge engine, which takes no part in making or tuning a map.

    The servo is the one model every engine shares (MujocoSettings' docstring): a proportional
    servo saturating at the URDF effort limit, with back-EMF damping effort / velocity limit.
    DART integrates joint damping implicitly, so the back-EMF term is stable at 240 Hz.
    """

    #: 240 Hz: the thesis's step, and the rate of the gait tables (one row per step).
    time_step: float = 1.0 / 240.0
    #: Physics steps per time step, the servo torque recomputed at each (960 Hz). The servo
    #: loop's own frequency, sqrt(kp / inertia), is about 240 rad/s on a tibia, and DART couples
    #: the proportional torque explicitly: at 240 Hz the control tripod and a locked leg's sag
    #: had not converged (0.283 m/s, 0.33 rad), at 960 Hz they had (0.294 m/s, 0.17 rad; the same
    #: within 0.1 % and 0.01 rad at 1920 Hz). Chosen by that step-halving check alone.
    substeps: int = 4
    #: ODE's narrow phase: neither PyBullet's (Bullet) nor MuJoCo's own; it collides the
    #: base's cylinder with boxes and the ground, which DART's own detector cannot.
    collision_detector: str = 'ode'
    #: The RX factory compliance slope, as in MujocoSettings (kp 21.2 / 31.7 N m/rad).
    compliance_slope: float = 32.0
    back_emf: bool = True

    def __post_init__(self) -> None:
        if not (math.isfinite(self.time_step) and 1e-4 <= self.time_step <= 0.01):
            raise ValueError(
                f'DART setting time_step must be in [0.0001, 0.01] s, got {self.time_step!r}'
            )
        if isinstance(self.substeps, bool) or not isinstance(self.substeps, int):
            raise ValueError(f'DART setting substeps must be an integer, got {self.substeps!r}')
        if not 1 <= self.substeps <= 64:
            raise ValueError(f'DART setting substeps must be in [1, 64], got {self.substeps}')
        if self.collision_detector not in DART_COLLISION_DETECTORS:
            raise ValueError(
                f'DART setting collision_detector must be one of '
                f'{", ".join(DART_COLLISION_DETECTORS)}, got {self.collision_detector!r}'
            )
        if not (math.isfinite(self.compliance_slope) and 1.0 <= self.compliance_slope <= 256.0):
            raise ValueError(
                f'DART setting compliance_slope must be in [1, 256], got {self.compliance_slope!r}'
            )


DART_DEFAULT_SETTINGS = DartSettings()
