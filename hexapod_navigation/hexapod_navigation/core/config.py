# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
How navigate pursues a goal: its settings (:class:`NavigationConfig`), the goal checks (ROS-free).

The settings of the learned correction (:mod:`hexapod_navigation.core.correction`), the planner
(:mod:`hexapod_navigation.core.planner`) and the episode loop
(:mod:`hexapod_navigation.core.episode`), each chosen on the tuning goals
(studies/navigation/README.md says how).
"""

from __future__ import annotations

from dataclasses import dataclass
import math

from hexapod_navigation.core.geometry import Pose2D

#: NavigationConfig.planner's choices
PLANNERS = ('nearest', 'time')
REST_SPEEDS = ('fastest', 'toward')


#: Where the tripod option's prior comes from (NavigationConfig.tripod_bank).
TRIPOD_BANK = ('off', 'always', 'evidence')


@dataclass(frozen=True)
class NavigationConfig:
    """How a goal is pursued; ValueError names a bad setting."""

    # Every default below was chosen on the tuning goals, never the reported ones:
    # studies/navigation/README.md has the table that chose each, and its round.
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
    #: prior std of a linear change of every step (damage that shrinks or turns all steps
    #: alike), on the intact displacement in metres (0: none)
    linear_std: float = 0.5
    #: the planner takes the step whose predicted end, moved this many standard deviations
    #: toward the goal, lies nearest it (GP-UCB). 0: with the damage bank, optimism only
    #: slowed the damaged goals
    optimism: float = 0.0
    #: only gaits that keep this many feet down at every instant: 3, because airborne gaits
    #: tip a damaged robot over (damaged goals reached 99.5 % against 74.8 % with all gaits)
    min_stance_legs: int = 3
    #: weigh the damage bank's step tables against the intact repertoire (when a bank is given
    #: and ``learn`` is on): on, the best on the damaged goals
    use_bank: bool = True
    #: with a bank: the intact repertoire's prior weight (0: every hypothesis alike)
    prior_intact: float = 0.0
    #: m: how far the truth may lie from a known model (the intact repertoire, a bank failure);
    #: > 0 gives the known models a GP this tight (heading: ``known_std_yaw``) and adds an
    #: 'unknown damage' hypothesis with weight ``prior_unknown``; 0 gives every hypothesis the
    #: GP above. 0.03, the smallest of the values that tied
    known_std_xy: float = 0.03
    known_std_yaw: float = 0.15  # rad
    prior_unknown: float = 0.2
    #: share of the known models' weight given to a damage the robot reported (its dead
    #: servos) that the bank models (0: reports unused). 0.5: a report saves 0.7 s of the
    #: median goal; believing it more saves nothing more
    prior_reported: float = 0.5
    #: optimism added in proportion to the weight of 'unknown damage' (0: none)
    unknown_optimism: float = 0.0
    #: how the planner scores a step: 'nearest' (the end nearest the goal, as RTE) or 'time'
    #: (the least expected time to the goal, counting the body's transition between gaits).
    #: 'time': faster to the damaged goals
    planner: str = 'time'
    #: 'time': a step's path reaches the goal where it comes this close, as a fraction of the
    #: tolerance (0.25 to 0.75 tie)
    aim: float = 0.5
    #: 'time': the speed assumed for the rest of the way after a step: 'fastest' (the longest
    #: predicted step) or 'toward' (the most progress toward the goal a step makes). 'toward':
    #: with 'fastest' a robot whose steps toward the goal are all short can mark time
    rest_speed: str = 'toward'
    #: 'time' with 'toward': the rest of the way is walked by this step's gait or by the best
    #: one after a transition, whichever is sooner (off: by the best, with no transition). On:
    #: 32 of 32 damage cells within the tripod's time, against 31
    rest_switch: bool = True
    #: the steered tripod's next cycle is a candidate too, learned as it walks
    #: (:class:`TripodSteps`): on damage the repertoire has no good step for, the robot walks
    #: the tripod instead of marking time
    tripod_option: bool = True
    #: the tripod becomes a candidate once this many repertoire steps in a row made less
    #: progress than the tripod's pace (0: from the first step, the best on all eight kinds)
    tripod_after: int = 0
    #: the tripod's prior: this fraction of its commanded stride, before it has walked
    tripod_prior: float = 1.0
    #: with a bank, the tripod's prior from its cycles under the bank's damages, mixed by how
    #: well each explains the steps walked: 'off', 'always', or 'evidence' (once something has
    #: been walked). 'evidence': 'always' never tries the tripod on damage the bank lacks
    tripod_bank: str = 'evidence'
    #: how many cycles' worth the bank's prior counts for in a direction the robot has walked
    tripod_bank_weight: float = 1.0
    #: 'evidence': a damage the robot reported counts as evidence for the tripod's prior too
    #: (on: the median goal 14.2 s against 14.7 s)
    tripod_reported: bool = True
    #: the default map's fastest gaits intact and under each of the bank's lifted legs as more
    #: steps (:mod:`hexapod_navigation.core.specialists`), when such a file is given. On: lifted
    #: legs 1.69 -> 1.39 x the intact time
    specialists: bool = True
    #: rad: only specialists whose step never tilts the body past this under any of the bank's
    #: damages (pi: all). 1.047, just under the 60 deg tip-over line: without it legs 3+5
    #: locked tipped over
    specialist_max_tilt: float = 1.047
    #: rad: a step that tilts the body past this is stopped and never taken again (pi: never).
    #: Off: at 0.52 rad it cut good steps short, and the robots it was for tip faster than
    #: standing can catch them. Only where the body streams its attitude (the simulators)
    tip_guard: float = math.pi
    #: rad: a step whose largest tilt, averaged over the bank's damages by belief, is past this
    #: is not taken (only the specialists are measured for tilt); pi: none. Not tuned
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
