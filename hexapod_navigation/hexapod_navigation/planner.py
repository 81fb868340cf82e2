# Copyright 2026 Hexapod adaptation team
# All rights reserved.
#
# Permission is hereby granted, free of charge, to any person obtaining a copy
# of this software and associated documentation files (the "Software"), to deal
# in the Software without restriction, including without limitation the rights
# to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
# copies of the Software, and to permit persons to whom the Software is
# furnished to do so, subject to the following conditions:
#
# The above copyright notice and this permission notice shall be included in all
# copies or substantial portions of the Software.
#
# THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
# IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
# FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
# AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
# LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
# OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
# SOFTWARE.
"""
Reaching a goal with a damaged robot, learning while it walks, with no resets (ROS-free).

Reset-free trial and error (Chatzilygeroudis, Vassiliades and Mouret 2018), adapted to a
crab-walking hexapod:

* a :class:`~hexapod_navigation.repertoire.Repertoire` of omnidirectional gaits, each indexed by
  the displacement one step (one execution, ``step_duration`` s) gives the intact robot;
* :class:`CorrectionGP`: one Gaussian process per displacement dimension (x, y, heading) over
  the repertoire's descriptor, learning from every step how the damage changes the steps;
* a planner (:class:`RepertoirePolicy`) that picks the step whose predicted end lies nearest
  the goal, from the pose the robot is actually in;
* :func:`hexapod_navigation.episode.run_episode` walks a body with them (the loop, its bodies).

The baseline :class:`~hexapod_navigation.tripod.SteeredTripod` is what the robot's firmware can
do: the control tripod, steered every cycle toward the goal in the nearest of its eight crab
directions; the planner weighs its next cycle too
(:class:`~hexapod_navigation.tripod.TripodSteps`).
Poses: :mod:`hexapod_navigation.geometry`; what a policy is: :mod:`hexapod_navigation.policy`.
"""

from __future__ import annotations

from dataclasses import dataclass
import math
from typing import Sequence

from hexapod_adapt.mapping.steps import REACH
from hexapod_adapt.online.mboa import mixture
from hexapod_gait import GaitParameters
from hexapod_navigation.geometry import Pose2D
from hexapod_navigation.policy import Step
from hexapod_navigation.repertoire import Repertoire
from hexapod_navigation.step_bank import StepBank
from hexapod_navigation.tripod import steered_direction, TripodSteps
from hexapod_sim.damage import Damage
import numpy as np
from scipy.linalg import solve_triangular

# -- settings and goals ------------------------------------------------------------------------
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
    #: docs/studies/navigation.md, sixth round)
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
    #: 'time' planner: the steered tripod's next cycle (the baseline's choice of crab direction)
    #: is a candidate too, with what the robot makes of such cycles learned as it walks
    #: (:class:`TripodSteps`). On a damage the repertoire has no good step for, the planner then
    #: walks the tripod instead of marking time (issue 31)
    tripod_option: bool = True
    #: the tripod becomes a candidate once the last this many repertoire steps made less progress
    #: toward the goal than the tripod's pace (0: from the first step; 0 was chosen on the tuning
    #: goals over 1 and 2, docs/studies/navigation.md "The tripod as an option")
    tripod_after: int = 0
    #: the tripod's prior: this fraction of its commanded stride, before the robot has walked it
    tripod_prior: float = 1.0
    #: with a damage bank, the tripod's prior may instead be its cycles under each of the bank's
    #: damages and intact, mixed by how well each explains the steps and cycles walked: 'off'
    #: (never), 'always', or 'evidence': once a step or cycle has been walked (before that, the
    #: stride above: the tripod is tried while nothing is known). 'always' was chosen on the
    #: tuning goals with the bank of lifted, locked and dead-femur legs (docs/studies/
    #: navigation.md, fifth round; with a bank of lifted legs only, 'off' was: it cost two
    #: locked-leg cells)
    tripod_bank: str = 'always'
    #: how many cycles' worth the bank's prior counts for in a direction the robot has walked
    tripod_bank_weight: float = 1.0

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


# -- the learned correction --------------------------------------------------------------------
class CorrectionGP:
    """
    Learned change of every repertoire step under damage: one GP per dimension (x, y, heading).

    Inputs are the repertoire's descriptors (each step's intact displacement); the prior mean is
    the intact step itself (heading change 0), so with no data the prediction is the repertoire.
    The kernel is a squared exponential (local changes) plus a linear kernel on the intact
    displacement (a change common to every step, e.g. all steps shorter or turned: learned from
    a few steps for the whole repertoire). Hyperparameters from NavigationConfig.

    ``hypotheses`` (h, n, 3), optional: other prior means, e.g. the steps re-measured under each
    one- and two-leg failure (:mod:`hexapod_navigation.step_bank`). Each, the intact repertoire
    among them, is weighted by its prior (``config.prior_intact``) times its marginal likelihood
    over the steps walked (the three dimensions' GPs together), and predictions are the mixture (as
    in :class:`hexapod_adapt.online.mboa.Mboa`).

    ``tripods`` (h + 1, 8, 3), optional with ``hypotheses``: the steered tripod's cycle in each
    crab direction under each hypothesis, intact first. Tripod cycles walked are evidence too
    (:meth:`add_tripod`: each hypothesis's cycle, with its group's signal variance and the
    noise), and :meth:`tripod_prior` is the weighted mixture of the cycles.

    With ``config.known_std_xy`` > 0 those known models get a tight GP of their own, and one
    more hypothesis, 'unknown damage' (the intact repertoire under the broad GP), comes last:
    the marginal likelihoods then compare different kernels, so they include each kernel's
    determinant (the broad one pays for explaining anything).

    ``reported``, optional: the row of ``hypotheses`` plus one (intact is 0) of a damage the robot
    reported; it gets ``config.prior_reported`` of the known models' prior weight.
    """

    def __init__(
        self,
        repertoire: Repertoire,
        config: NavigationConfig,
        hypotheses: np.ndarray | None = None,
        tripods: np.ndarray | None = None,
        reported: int | None = None,
    ) -> None:
        self.prior = np.column_stack([repertoire.moves, np.zeros(len(repertoire))])
        self.inputs = repertoire.moves / (2.0 * REACH)  # descriptor units
        self.config = config
        self.noise = np.array([config.noise_std_xy] * 2 + [config.noise_std_yaw]) ** 2
        self.observed: list[int] = []
        self.values: list[np.ndarray] = []
        means = [self.prior[None]]
        if hypotheses is not None:
            extra = np.asarray(hypotheses, dtype=float)
            if extra.size and extra.shape[1:] != self.prior.shape:
                raise ValueError(
                    f'each hypothesis needs a (dx, dy, dyaw) per repertoire step'
                    f' {self.prior.shape}, got shape {extra.shape[1:]}'
                )
            means.append(extra.reshape(-1, *self.prior.shape))
        known = len(np.concatenate(means))
        if reported is not None and not 0 < reported < known:
            raise ValueError(
                f'reported must name one of the {known - 1} hypotheses, got {reported}'
            )
        self.reported = reported
        self.signal = np.array([config.signal_std_xy] * 2 + [config.signal_std_yaw]) ** 2
        broad = (self.signal, 1.0)
        # kernel groups: (signal variance per dimension, linear part's scale, member rows)
        if config.known_std_xy > 0:
            tight = np.array([config.known_std_xy] * 2 + [config.known_std_yaw]) ** 2
            means.append(self.prior[None])  # 'unknown damage'
            self._groups = [(tight, 0.0, np.arange(known)), (*broad, np.array([known]))]
        else:
            self._groups = [(*broad, np.arange(known))]
        self._means = np.concatenate(means)  # (h, n, 3)
        self._mu_h = self._means.copy()
        self._log_prior = self._prior_weights(known, len(self._means))
        self._log_steps = self._log_prior.copy()  # the prior and the repertoire steps' evidence
        self._tripods: np.ndarray | None = None
        if tripods is not None:
            table = np.asarray(tripods, dtype=float)
            if table.shape != (known, 8, 3):
                raise ValueError(
                    f'tripods needs a (dx, dy, dyaw) per crab direction for the intact robot and'
                    f' each hypothesis {(known, 8, 3)}, got shape {table.shape}'
                )
            unknown = [table[:1]] if len(self._means) > known else []  # 'unknown': intact's
            self._tripods = np.concatenate([table, *unknown])
            self._tripod_var = np.empty((len(self._means), 3))
            for signal, _, rows in self._groups:
                self._tripod_var[rows] = signal + self.noise
        self._log_tripod = np.zeros(len(self._means))  # the tripod cycles' evidence
        self._cycles = 0  # tripod cycles learned from
        lin_ss = config.linear_std**2 * np.sum(repertoire.moves**2, axis=1)
        self._var_h = np.empty_like(self._means)  # each hypothesis's posterior variance
        for signal, linear, rows in self._groups:
            self._var_h[rows] = signal
            self._var_h[rows, :, :2] += linear * lin_ss[:, None]
        self._mix()

    def _prior_weights(self, known: int, total: int) -> np.ndarray:
        """Return the log prior of each hypothesis (intact first, 'unknown damage' last)."""
        c = self.config
        prior = np.ones(total)
        rest = 1.0
        if total > known:  # 'unknown damage'
            prior[known:] = c.prior_unknown
            rest -= c.prior_unknown
        if c.prior_intact > 0 and known > 1:
            prior[0] = c.prior_intact
            prior[1:known] = (rest - c.prior_intact) / (known - 1)
        else:
            prior[:known] = rest / known
        if self.reported is not None and c.prior_reported > 0:
            mass = prior[:known].sum()
            prior[:known] *= 1.0 - c.prior_reported
            prior[self.reported] += c.prior_reported * mass
        return np.log(prior)

    def _kernels(self, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Return the unit squared-exponential and the linear kernel between descriptor rows."""
        d2 = np.sum((a[:, None, :] - b[None, :, :]) ** 2, axis=-1)
        metres = (2.0 * REACH) ** 2
        return np.exp(-0.5 * d2 / self.config.length_scale**2), metres * (a @ b.T)

    def add(self, index: int, observed: Sequence[float]) -> None:
        """Learn one executed step: repertoire row ``index`` moved (dx, dy, dyaw)."""
        self.observed.append(int(index))
        self.values.append(np.asarray(observed, dtype=float))
        idx = np.array(self.observed)
        x = self.inputs[idx]
        se_xx, lin_xx = self._kernels(x, x)
        se_sx, lin_sx = self._kernels(self.inputs, x)  # (n, m)
        lin_ss = (2.0 * REACH) ** 2 * np.sum(self.inputs**2, axis=1)
        y = np.array(self.values)  # (m, 3)
        log_weight = self._log_prior.copy()
        for signal, linear, rows in self._groups:
            lin = linear * self.config.linear_std**2
            for d in range(3):
                # per dimension: K_d = s_d * SE + l * linear (the linear part: x and y only)
                ld = lin if d < 2 else 0.0
                a = signal[d] * se_xx + ld * lin_xx + self.noise[d] * np.eye(len(x))
                k_sx = signal[d] * se_sx + ld * lin_sx
                chol = np.linalg.cholesky(a)
                r = y[:, d][:, None] - self._means[rows][:, idx, d].T  # (m, h): residuals
                white = solve_triangular(chol, r, lower=True, check_finite=False)
                alpha = solve_triangular(chol.T, white, lower=False, check_finite=False)
                self._mu_h[rows, :, d] = self._means[rows, :, d] + (k_sx @ alpha).T
                log_det = np.sum(np.log(np.diag(chol)))  # half the log determinant
                log_weight[rows] -= 0.5 * np.sum(white * white, axis=0) + log_det
                v = solve_triangular(chol, k_sx.T, lower=True, check_finite=False)  # (m, n)
                prior_var = signal[d] + ld * lin_ss
                self._var_h[rows, :, d] = np.maximum(prior_var - np.sum(v * v, axis=0), 1e-12)
        self._log_steps = log_weight
        self._mix()

    def add_tripod(self, direction: int, observed: Sequence[float]) -> None:
        """Weigh the hypotheses by a tripod cycle of ``direction`` that moved (dx, dy, dyaw)."""
        if self._tripods is None:
            return
        self._cycles += 1
        r = np.asarray(observed, dtype=float)[None, :] - self._tripods[:, direction]
        v = self._tripod_var
        self._log_tripod -= 0.5 * np.sum(r * r / v + np.log(v), axis=1)
        self._mix()

    @property
    def evidence(self) -> int:
        """Return how many steps and tripod cycles the hypotheses were weighed on."""
        return len(self.observed) + self._cycles

    def tripod_prior(self) -> np.ndarray | None:
        """Return the tripod's expected cycle per direction (8, 3), None without ``tripods``."""
        if self._tripods is None:
            return None
        return np.einsum('h,hkd->kd', self.weights, self._tripods)

    def _mix(self) -> None:
        log_weight = self._log_steps + self._log_tripod
        self.weights, self._mean, self._var = mixture(log_weight, self._mu_h, self._var_h)

    def predict(self) -> tuple[np.ndarray, np.ndarray]:
        """Return every step's predicted (dx, dy, dyaw) (n, 3) and its variance (n, 3)."""
        return self._mean, self._var

    @property
    def unknown_weight(self) -> float:
        """Return the weight of 'unknown damage' (0 without known models)."""
        return float(self.weights[-1]) if len(self._groups) > 1 else 0.0


# -- policies ----------------------------------------------------------------------------------
def time_to_goal(
    start: tuple[float, float],
    ends: np.ndarray,
    goal: tuple[float, float],
    radius: float,
    step_time: float,
    switch: np.ndarray,
    speed: float,
) -> np.ndarray:
    """
    Return each step's expected time [s] until the robot is within ``radius`` of ``goal``.

    A step (row of ``ends`` (n, 2), where it ends) first spends ``switch`` (n,) s changing gait,
    then walks ``step_time`` s along the straight line from ``start`` to its end. If that line
    enters the goal circle, the time is the switch and the time into the step at which it does;
    otherwise the switch, the whole step, and the rest of the way from its end at ``speed`` m/s.
    """
    p0 = np.asarray(start, dtype=float)
    g = np.asarray(goal, dtype=float)
    ends = np.asarray(ends, dtype=float)
    d = ends - p0  # (n, 2): the step's chord
    length2 = np.maximum(np.sum(d * d, axis=1), 1e-12)
    # the chord's point nearest the goal, as a fraction f of the step
    f = np.clip((d @ (g - p0)) / length2, 0.0, 1.0)
    miss2 = np.sum((p0 + f[:, None] * d - g) ** 2, axis=1)
    inside = miss2 <= radius**2
    # walking back from the nearest point to where the chord enters the circle
    back = np.sqrt(np.maximum(radius**2 - miss2, 0.0) / length2)
    arrive = np.maximum(f - back, 0.0) * step_time
    after = np.hypot(*(g - ends).T)
    rest = step_time + np.maximum(after - radius, 0.0) / max(speed, 1e-6)
    return np.asarray(switch, dtype=float) + np.where(inside, arrive, rest)


class RepertoirePolicy:
    """
    The repertoire planner, with (``config.learn``) or without the GP correction.

    ``hypotheses``: a damage bank's step tables (:class:`hexapod_navigation.step_bank.StepBank`'s
    ``steps``), weighed when ``config.use_bank`` and ``config.learn``.
    """

    def __init__(
        self,
        repertoire: Repertoire,
        config: NavigationConfig,
        hypotheses: np.ndarray | None = None,
        tripods: np.ndarray | None = None,
        reported: int | None = None,
    ) -> None:
        self.repertoire = repertoire
        self.config = config
        use = config.use_bank and config.learn and hypotheses is not None
        self.gp = CorrectionGP(
            repertoire,
            config,
            hypotheses if use else None,
            tripods if use and config.tripod_bank != 'off' else None,
            reported if use else None,
        )
        self.tripod = TripodSteps(config.tripod_prior, config.tripod_bank_weight)
        self._goal: tuple[float, float] | None = None  # of the last step chosen
        self._made: list[tuple[float, float]] = []  # repertoire steps: (progress [m], time [s])
        self._gaits: dict[int, GaitParameters] = {}
        self.allowed = repertoire.min_stance() >= config.min_stance_legs
        if not self.allowed.any():
            raise ValueError(
                f'no repertoire gait keeps {config.min_stance_legs} feet on the ground throughout'
            )

    @classmethod
    def with_bank(
        cls,
        repertoire: Repertoire,
        config: NavigationConfig,
        bank: StepBank | None,
        reported: Damage | None = None,
    ) -> RepertoirePolicy:
        """
        Return the policy weighing ``bank``'s steps and tripod cycles (None: no bank).

        ``reported``: the damage the robot reported (its dead servos), favoured as
        ``config.prior_reported`` says when the bank models it (:meth:`StepBank.index_of`).
        """
        if bank is None:
            return cls(repertoire, config)
        row = bank.index_of(reported) if reported is not None else None
        return cls(
            repertoire, config, bank.steps, bank.tripods(), None if row is None else row + 1
        )

    def next_step(
        self,
        pose: Pose2D,
        goal: tuple[float, float],
        playing: GaitParameters | None = None,
        switch_time: float = 0.0,
    ) -> Step:
        """
        Return the best step from ``pose`` by ``config.planner`` (one step ahead).

        Both planners move each predicted end ``optimism`` standard deviations toward the goal
        (a lower confidence bound on the distance left). 'nearest' takes the step that then ends
        nearest the goal; 'time' the one with the least expected time to it
        (:func:`time_to_goal`), the steered tripod's cycles included (``tripod_option``).
        """
        mean, var = self.gp.predict()
        c, s = math.cos(pose.yaw), math.sin(pose.yaw)
        ex = pose.x + c * mean[:, 0] - s * mean[:, 1]
        ey = pose.y + s * mean[:, 0] + c * mean[:, 1]
        left = np.hypot(goal[0] - ex, goal[1] - ey)
        optimism = self.config.optimism + self.config.unknown_optimism * self.gp.unknown_weight
        shift = optimism * np.sqrt(var[:, 0] + var[:, 1])
        playing_row = next((i for i, g in self._gaits.items() if g is playing), -1)
        switch = np.full(len(mean), float(switch_time))
        if playing_row >= 0:
            switch[playing_row] = 0.0
        if self.config.planner == 'nearest':
            cost = left - shift
            i = int(np.argmin(np.where(self.allowed, cost, np.inf)))
            return self._repertoire_step(i, pose, mean, switch)
        # the end moved toward the goal by the optimism's shift (no further than the goal)
        pull = np.minimum(shift, left) / np.maximum(left, 1e-12)
        ends = np.column_stack([ex + pull * (goal[0] - ex), ey + pull * (goal[1] - ey)])
        to_goal = np.array([goal[0] - pose.x, goal[1] - pose.y])
        unit = to_goal / max(float(np.hypot(*to_goal)), 1e-12)
        if self.config.rest_speed == 'toward':
            # each step's progress toward the goal from here (the chord's projection); a
            # floor of 1 mm per step: no step that heads for the goal is a big cost, not an
            # infinite one
            progress = (ex - pose.x) * unit[0] + (ey - pose.y) * unit[1]
            best = max(float(np.max(progress[self.allowed])), 1e-3)
        else:
            best = float(np.max(np.hypot(mean[:, 0], mean[:, 1])[self.allowed]))
        radius = self.config.aim * self.config.tolerance
        step = self.repertoire.step_duration
        cost = time_to_goal((pose.x, pose.y), ends, goal, radius, step, switch, best / step)
        i = int(np.argmin(np.where(self.allowed, cost, np.inf)))
        self._goal = goal
        if self.config.tripod_option:
            # the steered tripod's next cycle (the crab direction nearest the goal's bearing, as
            # the baseline walks it), where the robot has been making such cycles go, and the
            # rest of the way at the tripod's own pace: the time if the robot commits to it. It
            # is a candidate once the repertoire's last steps made less progress than that pace
            # (the repertoire has had its chance to learn the damage)
            k = steered_direction(pose, goal)
            bank = self.config.tripod_bank == 'always' or self.gp.evidence > 0
            cycle = self.tripod.displacement(self.gp.tripod_prior() if bank else None)[k]
            dx, dy = cycle[0], cycle[1]
            end = np.array([[pose.x + c * dx - s * dy, pose.y + s * dx + c * dy]])
            gait = self.tripod.gaits[k]
            tripod_switch = 0.0 if gait is playing else float(switch_time)
            pace = max(float((end[0] - (pose.x, pose.y)) @ unit), 1e-3) / self.tripod.period
            tripod_cost = time_to_goal(
                (pose.x, pose.y), end, goal, radius, self.tripod.period, [tripod_switch], pace
            )[0]
            n = self.config.tripod_after
            made = self._made[-n:] if n else []
            lagging = len(made) == n and sum(p for p, _ in made) <= pace * sum(t for _, t in made)
            if lagging and tripod_cost < cost[i]:
                predicted = pose.moved(*cycle)
                return Step(gait, self.tripod.period + tripod_switch, predicted, tripod=k)
        return self._repertoire_step(i, pose, mean, switch)

    def _repertoire_step(self, i: int, pose: Pose2D, mean: np.ndarray, switch: np.ndarray) -> Step:
        if i not in self._gaits:
            self._gaits[i] = self.repertoire.gait(i)
        predicted = pose.moved(*mean[i])
        return Step(self._gaits[i], self.repertoire.step_duration + switch[i], predicted, i)

    def observe(self, step: Step, start: Pose2D, end: Pose2D, completed: bool) -> float | None:
        """Learn a whole step (a cut-short one teaches nothing); return its prediction error."""
        if not completed:
            return None
        error = end.distance_to(step.predicted.x, step.predicted.y)
        if step.tripod >= 0:
            moved = start.relative(end)
            self.tripod.observe(step.tripod, moved)
            if self.config.learn:
                self.gp.add_tripod(step.tripod, moved)
            return error
        if self._goal is not None:  # the progress it made toward the goal it was taken for
            g = self._goal
            made = start.distance_to(*g) - end.distance_to(*g)
            self._made.append((made, step.duration))
        if self.config.learn:
            self.gp.add(step.index, start.relative(end))
        return error
