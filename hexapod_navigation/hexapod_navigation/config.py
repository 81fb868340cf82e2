# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
How navigate pursues a goal: its settings (:class:`NavigationConfig`), the goal checks (ROS-free).

The settings of the learned correction (:mod:`hexapod_navigation.correction`), the planner
(:mod:`hexapod_navigation.planner`) and the episode loop (:mod:`hexapod_navigation.episode`),
each chosen on the tuning goals (studies/navigation/README.md says how).
"""

from __future__ import annotations

from dataclasses import dataclass
import math

from hexapod_navigation.geometry import Pose2D

#: NavigationConfig.planner's choices
PLANNERS = ('nearest', 'time')
REST_SPEEDS = ('fastest', 'toward')


#: Where the tripod option's prior comes from (NavigationConfig.tripod_bank).
TRIPOD_BANK = ('off', 'always', 'evidence')


@dataclass(frozen=True)
class NavigationConfig:
    """How a goal is pursued; ValueError names a bad setting."""

    tolerance: float = 0.15  # m: reached when this close
    time_limit: float = 90.0  # s of walking
    max_range: float = 10.0  # m: farther goals are refused
    arena: float | None = None  # m: leaving the square |x|, |y| <= arena fails the goal
    learn: bool = True  # the GP correction (False: the repertoire as it was measured intact)
    length_scale: float = 0.15  # GP kernel length scale, in descriptor units (2 REACH = 1)
    signal_std_xy: float = 0.2  # m: how far damage may move a step's end, a priori
    signal_std_yaw: float = 0.5  # rad: how much damage may turn a step, a priori
    noise_std_xy: float = 0.03  # m: repeatability of one step
    noise_std_yaw: float = 0.05  # rad
    #: prior std of a linear change of every step (damage that shrinks or turns all steps alike):
    #: the kernel's linear part, on the intact displacement in metres (0: none)
    linear_std: float = 0.5
    #: optimism of the planner: it takes the step whose predicted end, moved ``optimism``
    #: standard deviations toward the goal, lies nearest it (a lower confidence bound on the
    #: distance left, as GP-UCB). 0: the predicted end alone. Without a damage bank that can
    #: settle on a step known to go nowhere once every step is predicted short (1 was the
    #: setting then); with the bank, 0 was the best on the tuning goals (docs/navigation.md).
    optimism: float = 0.0
    #: only gaits that keep at least this many feet on the ground at every instant of their
    #: cycle: most repertoire gaits have airborne phases, and a damaged robot tips over on them
    #: (3: chosen on the tuning goals, docs/navigation.md "Tuning")
    min_stance_legs: int = 3
    #: weigh the damage bank's step tables (hexapod_navigation.step_bank) against the intact
    #: repertoire, when one is given and ``learn`` is on (chosen on the tuning goals)
    use_bank: bool = True
    #: with a bank: the intact repertoire's prior weight among the hypotheses (the bank's
    #: failures share the rest alike); 0: every hypothesis alike
    prior_intact: float = 0.0
    #: m: how far the truth may lie from a known model of the robot (the intact repertoire, a
    #: bank's failure): 0 gives every hypothesis the GP above (signal_std_*, linear_std), so a
    #: few steps hardly tell them apart. > 0 gives the known models a GP this tight (heading:
    #: ``known_std_yaw``, no linear part), and adds one 'unknown damage' hypothesis, the intact
    #: repertoire with the GP above, with prior weight ``prior_unknown`` (0.03: chosen on the
    #: tuning goals, docs/navigation.md "Known models"; known_std_yaw and prior_unknown were set
    #: before and not tuned)
    known_std_xy: float = 0.03
    known_std_yaw: float = 0.15  # rad
    prior_unknown: float = 0.2
    #: a damage reported by the robot (its dead servos, from the bridge) that the bank models:
    #: this share of the known models' prior weight goes to it, the rest as without a report
    #: (0: reports are not used; 0.5 chosen on the tuning goals over 0 and 0.9,
    #: studies/navigation/README.md, sixth round)
    prior_reported: float = 0.5
    #: optimism added in proportion to the weight of 'unknown damage': when no known model
    #: fits, the planner looks beyond steps the GP predicts short (0: none)
    unknown_optimism: float = 0.0
    #: how the planner scores a step: 'nearest', the step whose end lies nearest the goal (as
    #: RTE); 'time', the step with the least expected time to the goal: the gait change it
    #: costs (the body's transition), the time into the step at which its path enters the goal
    #: circle, or else the whole step and the rest of the way at the fastest predicted step's
    #: speed ('time': chosen on the tuning goals, docs/navigation.md)
    planner: str = 'time'
    #: 'time' planner: a step's path counts as reaching the goal where it comes this close to
    #: it, as a fraction of the tolerance (the path within a step is taken as straight)
    aim: float = 0.5
    #: 'time' planner: the speed assumed for the rest of the way after a step. 'fastest': the
    #: longest predicted step, in any direction; 'toward': the most progress toward the goal a
    #: predicted step makes from where the robot is. With 'fastest', when every step that
    #: heads for the goal is predicted short, a gait that barely moves costs less than the
    #: transition to another, and the robot can mark time until the time limit ('toward':
    #: chosen on the tuning goals, docs/navigation.md "Rest of the way")
    rest_speed: str = 'toward'
    #: 'time' planner with 'toward': the rest of the way after a step is walked either by that
    #: step's own gait (at the progress it makes, no transition) or by the one that makes the
    #: most (after the body's transition to it), whichever is sooner. Off: at the most progress,
    #: with no transition, so a step that only bridges to a better gait looks as good as that
    #: gait. On, chosen on the tuning goals of all eight kinds with the specialists' 962 variants
    #: (studies/navigation/README.md, sixteenth round: 32 of 32 cells, lifted 1.365 x the intact
    #: time, against 31 of 32 off)
    rest_switch: bool = True
    #: 'time' planner: the steered tripod's next cycle (the baseline's choice of crab direction)
    #: is a candidate too, with what the robot makes of such cycles learned as it walks
    #: (:class:`TripodSteps`). On a damage the repertoire has no good step for, the planner then
    #: walks the tripod instead of marking time (issue 31)
    tripod_option: bool = True
    #: the tripod becomes a candidate once the last this many repertoire steps made less progress
    #: toward the goal than the tripod's pace (0: from the first step). 0, chosen on the tuning
    #: goals of all eight damage kinds over 1 and 2 (studies/navigation/README.md, ninth round: 29
    #: of 32 cells at <= 1.05x the tripod's time, against 27 and 27; the seventh round, on four
    #: kinds without weak legs, had chosen 2)
    tripod_after: int = 0
    #: the tripod's prior: this fraction of its commanded stride, before the robot has walked it
    tripod_prior: float = 1.0
    #: with a damage bank, the tripod's prior may instead be its cycles under each of the bank's
    #: damages and intact, mixed by how well each explains the steps and cycles walked: 'off'
    #: (never), 'always', or 'evidence': once a step or cycle has been walked (before that, the
    #: stride above: the tripod is tried while nothing is known). 'evidence', chosen on the tuning
    #: goals of all eight damage kinds (studies/navigation/README.md, tenth round: 32 of 32 cells
    #: at <= 1.05x the tripod's time against 'always''s 29, which lost weak legs: damage the bank
    #: lacks, on which its mixture predicts a short cycle and the tripod is never tried)
    tripod_bank: str = 'evidence'
    #: how many cycles' worth the bank's prior counts for in a direction the robot has walked
    tripod_bank_weight: float = 1.0
    #: 'evidence': a damage the robot reported (its dead servos) that the bank models counts as
    #: evidence too, so the tripod's first cycle is weighed under it instead of at the commanded
    #: stride. On, chosen on the tuning goals of the kinds a report names and the bank models
    #: (studies/navigation/README.md, eleventh round: 8 of 8 cells either way, median goal 14.2 s
    #: against 14.7 s)
    tripod_reported: bool = True
    #: with a damage bank: the default map's fastest gaits intact and under each of the bank's
    #: lifted legs, as more steps (:mod:`hexapod_navigation.specialists`), when a file of them
    #: measured under the bank's damages is given. On: on the tuning goals of all eight kinds,
    #: with specialist_max_tilt below, they bring the lifted legs from 1.69 to 1.39 x the intact
    #: time and pass all 32 cells against the tripod (studies/navigation/README.md, rounds 12-15;
    #: at eight crab angles and three strides, with rest_switch, 1.365 x, round 16)
    specialists: bool = True
    #: rad: only specialists whose step from rest never tilts the body (roll or pitch) more than
    #: this under any damage of the bank (pi: all). A gait made for one damage can tip the robot
    #: over under another: 1.047, just under the tip-over line
    #: (hexapod_sim.simulator.TIP_OVER_DEG, 60 deg), kept 87 of the 94 of the fifteenth round
    #: (legs 3+5 locked tipped over without it)
    specialist_max_tilt: float = 1.047
    #: rad: a step that tilts the body (roll or pitch) past this is stopped, the robot stands,
    #: and the policy never takes that step again (:class:`hexapod_navigation.policy.Policy`'s
    #: ``avoid``); pi: never. Where the body streams its attitude (the simulators, sim_node):
    #: a trial on the robot through bridge_node is not stopped midway. Off: at 0.52 rad it cut
    #: legit steps short (no_tibia S4 1.16 x the tripod), and the robots it was for tip faster
    #: than standing can catch them (studies/navigation/README.md, rounds 13-14)
    tip_guard: float = math.pi
    #: rad: a step whose largest tilt, averaged over the bank's damages by how much the robot
    #: believes in each (the correction's hypothesis weights), is past this is not taken; only
    #: steps measured for tilt (the specialists) can be held back; pi: none (tried on two kinds
    #: only, studies/navigation/README.md; not tuned)
    expected_tilt_limit: float = math.pi

    def __post_init__(self) -> None:
        for name in (
            'tolerance',
            'time_limit',
            'max_range',
            'length_scale',
            'signal_std_xy',
            'signal_std_yaw',
            'noise_std_xy',
            'noise_std_yaw',
        ):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f'{name} must be a positive finite number, got {value!r}')
        for name in ('specialist_max_tilt', 'tip_guard', 'expected_tilt_limit'):
            tilt = getattr(self, name)
            if not (isinstance(tilt, (int, float)) and 0.0 < tilt <= math.pi):
                raise ValueError(f'{name} must be in (0, pi] rad, got {tilt!r}')
        for name in ('optimism', 'linear_std', 'unknown_optimism'):
            w = getattr(self, name)
            if not (isinstance(w, (int, float)) and math.isfinite(w) and w >= 0):
                raise ValueError(f'{name} must be a finite number >= 0, got {w!r}')
        if self.planner not in PLANNERS:
            raise ValueError(f'planner must be one of {PLANNERS}, got {self.planner!r}')
        if self.rest_speed not in REST_SPEEDS:
            raise ValueError(f'rest_speed must be one of {REST_SPEEDS}, got {self.rest_speed!r}')
        if not (isinstance(self.aim, (int, float)) and 0.0 < self.aim <= 1.0):
            raise ValueError(
                f'aim must be a fraction of the tolerance in (0, 1], got {self.aim!r}'
            )
        for name in ('known_std_xy', 'known_std_yaw'):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
                raise ValueError(f'{name} must be a finite number >= 0 (0: off), got {value!r}')
        if not (isinstance(self.prior_unknown, (int, float)) and 0.0 < self.prior_unknown < 1.0):
            raise ValueError(
                f'prior_unknown must be a probability in (0, 1), got {self.prior_unknown!r}'
            )
        if not (
            isinstance(self.prior_reported, (int, float)) and 0.0 <= self.prior_reported < 1.0
        ):
            raise ValueError(
                f'prior_reported must be a share in [0, 1) (0: off), got {self.prior_reported!r}'
            )
        if not (isinstance(self.prior_intact, (int, float)) and 0.0 <= self.prior_intact < 1.0):
            raise ValueError(
                'prior_intact must be a probability in [0, 1) (0: none),'
                f' got {self.prior_intact!r}'
            )
        if self.known_std_xy > 0 and self.prior_intact + self.prior_unknown >= 1.0:
            raise ValueError(
                'prior_intact + prior_unknown must leave the bank some weight (< 1), got'
                f' {self.prior_intact!r} + {self.prior_unknown!r}'
            )
        if not (isinstance(self.tripod_prior, (int, float)) and 0.0 <= self.tripod_prior <= 1.0):
            raise ValueError(
                f'tripod_prior must be a fraction in [0, 1], got {self.tripod_prior!r}'
            )
        w = self.tripod_bank_weight
        if not (isinstance(w, (int, float)) and 0.0 < w <= 100.0):
            raise ValueError(f'tripod_bank_weight must be in (0, 100] cycles, got {w!r}')
        if self.tripod_bank not in TRIPOD_BANK:
            raise ValueError(
                f'tripod_bank must be one of {", ".join(TRIPOD_BANK)}, got {self.tripod_bank!r}'
            )
        if not (isinstance(self.tripod_after, int) and 0 <= self.tripod_after <= 100):
            raise ValueError(f'tripod_after must be 0..100 steps, got {self.tripod_after!r}')
        if not (isinstance(self.min_stance_legs, int) and 0 <= self.min_stance_legs <= 6):
            raise ValueError(f'min_stance_legs must be 0..6, got {self.min_stance_legs!r}')
        if self.arena is not None and not (math.isfinite(self.arena) and self.arena > 0):
            raise ValueError(f'arena must be a positive finite half-width [m], got {self.arena!r}')


def goal_problem(x: float, y: float, start: Pose2D | None, config: NavigationConfig) -> str:
    """
    Why a goal (x, y) in odom cannot be pursued from ``start`` ('' if it can).

    ``start`` None (no pose yet): what does not depend on where the robot is.
    """
    if not (math.isfinite(x) and math.isfinite(y)):
        return f'the goal ({x}, {y}) is not a finite position'
    far = start.distance_to(x, y) if start is not None else 0.0
    if far > config.max_range:
        return (
            f'the goal is {far:.2f} m away, beyond the configured range of {config.max_range:g} m'
        )
    if config.arena is not None and max(abs(x), abs(y)) > config.arena:
        return (
            f'the goal ({x:.2f}, {y:.2f}) lies outside the arena (|x|, |y| <= {config.arena:g} m)'
        )
    return ''
