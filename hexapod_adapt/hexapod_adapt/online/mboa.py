# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Map-based Bayesian optimisation, M-BOA (thesis algorithm 2, Cully et al. 2015); ROS-free.

A Gaussian process over the behaviour descriptors of the map's elites models the real speed
of each elite. Its prior mean is the speed the map predicts (simulation, intact robot); the
kernel is Matern 5/2 with length scale rho and unit signal variance; observations carry noise
variance ``noise`` (0.001 in the papers -- set explicitly, never a library default).

    next trial  = argmax_x  mu_t(x) + kappa * sigma_t(x)            (UCB, sigma = std dev)
    stop when   max measured >= alpha * max_x mu_t(x), or after max_trials trials

Our addition, a success floor (``min_speed``, 0 in the thesis): the relative rule alone can call
a near-standstill a success once poor trials pull the whole posterior down, so success also needs
the best measured speed to reach the floor. Below it the run goes on, and ends unsuccessful at
the trial budget or when the map is used up.

Our second addition, damage hypotheses (``hypotheses``, none in the thesis): other prior means
the damage may explain, e.g. the map re-scored in simulation under each one- and two-leg failure
(a damage bank, :mod:`hexapod_adapt.online.bank`). The GP is the same under each; only its mean
differs. Each hypothesis h (the map's own speeds among them) is weighted by how well it explains
the trials, its marginal likelihood ``exp(-r_h / 2)`` with ``r_h = (y - m_h)^T (K + noise I)^-1 (y
- m_h)``, and M-BOA works on the mixture: mean ``sum_h w_h mu_h``, variance ``sigma^2 + sum_h w_h
(mu_h - mean)^2``. The first trials then also tell the hypotheses apart (Pautrat, Chatzilygeroudis
and Mouret 2018 pick the single most likely prior instead).

An elite already tried is not offered again: the next-best untried elite is (re-testing the
same gait would only average its noise; see ``MboaConfig.exclude_tested``).
Speeds are in m/s throughout.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import enum
import math

from hexapod_sim.evaluation import TRIAL_DURATION as SIM_TRIAL_DURATION
import numpy as np
from scipy.linalg import solve_triangular
from scipy.special import ndtr
from threadpoolctl import threadpool_limits

SQRT_2PI = math.sqrt(2.0 * math.pi)


class StopReason(enum.Enum):
    """Why an M-BOA run stops: thesis 5.2.2's stopping rule, the trial budget or a used-up map."""

    CONTINUE = 'continue'
    ALPHA_REACHED = 'alpha_reached'  # best measured >= alpha x highest posterior mean: success
    MAX_TRIALS = 'max_trials'
    MAP_EXHAUSTED = 'map_exhausted'


#: Documented limits of the run settings (the Adapt service refuses values outside them).
MAX_TRIALS_LIMIT = 1000  # the thesis's longest real run took 35 trials
MIN_SPEED_RANGE = (0.0, 2.0)  # m/s: the success floor (no gait of this robot walks 2 m/s)
LENGTH_SCALE_RANGE = (1e-3, 10.0)  # descriptor units: the duty-factor cube's diagonal is 2.45
NOISE_RANGE = (1e-9, 1.0)  # (m/s)^2: a trial speed's variance, 1 = +/-1 m/s
KAPPA_RANGE = (0.0, 100.0)
ALPHA_RANGE = (0.05, 1.0)  # stop ratio: below 5 % any forward step would "succeed"
SIGNAL_VARIANCE_RANGE = (1e-6, 10.0)  # (m/s)^2: the kernel's variance
OFFSET_STD_RANGE = (0.0, 1.0)  # m/s: a speed shift every gait shares (0 = none)
STOP_GAIN_RANGE = (1e-6, 1.0)  # m/s: expected gain of one more trial worth walking it
KNOWN_STD_RANGE = (0.0, 1.0)  # m/s: spread of the truth about a known model (0 = off)
PRIOR_UNKNOWN_RANGE = (1e-3, 0.999)  # prior weight of 'unknown damage' among the hypotheses


@dataclass(frozen=True)
class MboaConfig:
    """M-BOA settings (thesis 5.2.2 defaults); ValueError names every value out of range."""

    max_trials: int = 24  # TRIAL_BUDGET: 2 minutes of 5 s trials
    alpha: float = 0.90  # stop ratio
    kappa: float = 0.05  # UCB exploration weight (times the standard deviation)
    length_scale: float = 0.4  # rho, in descriptor units (duty factor, 0..1)
    noise: float = 0.001  # observation noise variance [(m/s)^2]
    exclude_tested: bool = True
    min_speed: float = 0.0  # success floor [m/s]: no success while the best is slower
    signal_variance: float = 1.0  # kernel variance [(m/s)^2]: how far damage moves speeds
    #: [m/s] std of a shift of the map's speeds shared by every gait, a constant term in the
    #: kernel: trials that all walk slower than the map lower every untried gait's prediction
    #: (a damage that slows the whole map). 0: none, the thesis's GP
    offset_std: float = 0.0
    #: [m/s] the same shift for a run from a known damage's prior (a servo report): the
    #: re-score's speeds are the map engine's, and on other physics every gait may walk slower
    #: than they say (``session.run_rules``). 0: none, the thesis's GP
    prior_offset_std: float = 0.0
    #: [m/s] also go on while an untried gait's expected gain exceeds it (None: no such stop,
    #: alpha and max_trials alone). A session from a known damage's prior stops on alpha alone
    #: (``session.run_rules``), its first trial being the re-scored map's best
    stop_gain: float | None = None
    use_bank: bool = False  # weigh a damage bank's hypotheses when the damage is not known
    #: [m/s] with hypotheses: how far the truth may lie from a known model (the map, a bank's
    #: failure), the std of a GP of their own; one 'unknown damage' hypothesis (the map under
    #: the kernel above) is added with prior weight ``prior_unknown``. 0: one GP for all
    known_std: float = 0.0
    prior_unknown: float = 0.2

    def __post_init__(self) -> None:
        problems = []

        def within(name: str, value: float, low: float, high: float, unit: str = '') -> None:
            if not (
                isinstance(value, (int, float)) and math.isfinite(value) and low <= value <= high
            ):
                problems.append(f'{name} must be in [{low:g}, {high:g}]{unit} (got {value!r})')

        if (
            isinstance(self.max_trials, bool)
            or not isinstance(self.max_trials, int)
            or not 1 <= self.max_trials <= MAX_TRIALS_LIMIT
        ):
            problems.append(
                f'max_trials must be an integer in [1, {MAX_TRIALS_LIMIT}] (got'
                f' {self.max_trials!r})'
            )
        within('alpha (stop ratio)', self.alpha, *ALPHA_RANGE)
        within('kappa', self.kappa, *KAPPA_RANGE)
        within('length_scale (rho)', self.length_scale, *LENGTH_SCALE_RANGE, ' descriptor units')
        within('noise variance', self.noise, *NOISE_RANGE, ' (m/s)^2')
        within('min_speed (success floor)', self.min_speed, *MIN_SPEED_RANGE, ' m/s')
        within('signal_variance', self.signal_variance, *SIGNAL_VARIANCE_RANGE, ' (m/s)^2')
        within('offset_std', self.offset_std, *OFFSET_STD_RANGE, ' m/s')
        within('prior_offset_std', self.prior_offset_std, *OFFSET_STD_RANGE, ' m/s')
        if self.stop_gain is not None:
            within('stop_gain', self.stop_gain, *STOP_GAIN_RANGE, ' m/s')
        within('known_std', self.known_std, *KNOWN_STD_RANGE, ' m/s')
        within('prior_unknown', self.prior_unknown, *PRIOR_UNKNOWN_RANGE)
        if problems:
            raise ValueError('; '.join(problems))


#: Named M-BOA settings. ``thesis``: thesis 5.2.2. ``default``: the best worst-case ratio to
#: the ceiling on a tuning set of other maps and other damage kinds; a kernel variance of 0.01
#: (m/s)^2 because damage moves speeds by about that much (studies/adaptation/README.md).
#: max_trials is the caller's budget.
PROFILES: dict[str, MboaConfig] = {
    'thesis': MboaConfig(),
    'default': MboaConfig(
        alpha=0.95,
        kappa=0.5,
        length_scale=0.3,
        noise=0.001,
        signal_variance=0.01,
        stop_gain=0.002,
        # prior_offset_std stays 0: 0.05 m/s won on a tuning set of MuJoCo physics variants and
        # cost the judge's prior runs 0.020 m/s (studies/adaptation/README.md, "The prior's
        # shared shift")
    ),
}
DEFAULT_PROFILE = 'default'
#: The trial budget users get: 2 minutes of 5 s trials (MboaConfig's default).
TRIAL_BUDGET = MboaConfig().max_trials
#: The trial users get: 5 s timed from standing, the thesis's and the maps' (one home:
#: hexapod_sim's). Shorter settled trials pick gaits that fall or turn back on another engine
#: (studies/trial_length/README.md).
TRIAL_DURATION = SIM_TRIAL_DURATION  # s timed
TRIAL_SETTLE = 0.0  # s walked before the timing starts


def profile(name: str) -> MboaConfig:
    """Return the named settings; ValueError lists the names."""
    if name not in PROFILES:
        raise ValueError(f'unknown M-BOA profile {name!r}; choose one of: {", ".join(PROFILES)}')
    return PROFILES[name]


def matern52(a: np.ndarray, b: np.ndarray, length_scale: float) -> np.ndarray:
    """Matern 5/2 kernel matrix between rows of a (n, d) and b (m, d), unit variance."""
    d = np.sqrt(np.maximum(((a[:, None, :] - b[None, :, :]) ** 2).sum(-1), 0.0)) / length_scale
    s5d = math.sqrt(5.0) * d
    return (1.0 + s5d + 5.0 / 3.0 * d * d) * np.exp(-s5d)


def _solve_lower(a: np.ndarray, b: np.ndarray, upper: bool = False) -> np.ndarray:
    """Solve a triangular system (a lower, or upper if ``upper``) for one right-hand side."""
    return solve_triangular(a, b, lower=not upper, check_finite=False)


def mixture(
    log_weight: np.ndarray, means: np.ndarray, variance: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """
    Return (weights, mean, variance) of a mixture of GP posteriors.

    ``log_weight`` (h,): each hypothesis's log marginal likelihood (up to a shared constant);
    ``means`` (h, ...): its posterior mean; ``variance``: the posterior variance they share, or
    one per hypothesis (shape of ``means``: GPs with different kernels), then weighted. The
    mixture's variance adds the spread of the means. One hypothesis gives its own mean and
    variance exactly.
    """
    w = np.exp(log_weight - np.max(log_weight))
    w /= w.sum()
    mean = np.tensordot(w, means, axes=1)
    if np.shape(variance) == np.shape(means):
        variance = np.tensordot(w, variance, axes=1)
    return w, mean, variance + np.tensordot(w, (means - mean) ** 2, axes=1)


@dataclass
class Trial:
    """One trial of an M-BOA run: what was predicted and what was measured."""

    number: int  # 1-based
    index: int  # candidate index (row of the descriptors given to Mboa)
    predicted: float  # map prior at that elite [m/s]
    gp_mean: float  # posterior mean before the trial [m/s]
    gp_std: float
    measured: float  # [m/s]
    tipped: bool = False  # the tip guard stopped it: a failed trial, never tried again


@dataclass
class Mboa:
    """
    M-BOA over ``descriptors`` (m, 6) with prior speeds ``prior`` (m,).

    ``hypotheses`` (h, m), optional: other prior means, weighed against ``prior`` by the trials
    (see the module's docstring). Without them this is the thesis's M-BOA exactly.
    """

    descriptors: np.ndarray
    prior: np.ndarray
    config: MboaConfig = field(default_factory=MboaConfig)
    trials: list[Trial] = field(default_factory=list)
    hypotheses: np.ndarray | None = None
    #: candidates never to try, e.g. gaits that tip in a simulation of the damage (:meth:`veto`)
    vetoed: set[int] = field(default_factory=set)

    def __post_init__(self) -> None:
        self.descriptors = np.atleast_2d(np.asarray(self.descriptors, dtype=float))
        self.prior = np.asarray(self.prior, dtype=float)
        if len(self.descriptors) == 0 or self.prior.shape != (len(self.descriptors),):
            raise ValueError(
                f'need one prior speed per descriptor, got {self.prior.shape} for '
                f'{len(self.descriptors)} descriptors'
            )
        if not (np.all(np.isfinite(self.descriptors)) and np.all(np.isfinite(self.prior))):
            raise ValueError(
                'descriptors and prior speeds must be finite (pass only filled niches)'
            )
        means = [self.prior[None, :]]
        if self.hypotheses is not None:
            extra = np.atleast_2d(np.asarray(self.hypotheses, dtype=float))
            if extra.size and (extra.ndim != 2 or extra.shape[1] != len(self.prior)):
                raise ValueError(
                    f'each hypothesis needs one speed per descriptor ({len(self.prior)}),'
                    f' got shape {extra.shape}'
                )
            if not np.all(np.isfinite(extra)):
                raise ValueError('hypothesis speeds must be finite')
            means.append(extra.reshape(-1, len(self.prior)))
        # known models under a tight GP of their own, and 'unknown damage' last (the map under
        # the broad kernel): only with hypotheses, and known_std > 0
        self._known = 0
        if self.config.known_std > 0 and len(means) > 1:
            self._known = sum(len(m) for m in means)
            means.append(self.prior[None, :])
        self._means = np.vstack(means)  # (h, m): the prior mean under each hypothesis
        self._log_prior = np.zeros(len(self._means))
        if self._known:
            unknown = self.config.prior_unknown
            self._log_prior[:] = math.log((1.0 - unknown) / self._known)
            self._log_prior[-1] = math.log(unknown)
        self._log_weight = np.zeros(len(self._means))  # log marginal likelihoods (+ const)
        self._mu_h = self._means.copy()  # posterior mean under each hypothesis
        self._gp_var = np.full(len(self.prior), self._prior_variance())
        self._known_var = np.full(len(self.prior), self.config.known_std**2)
        self._mix()
        # Incremental GP state (one column / row per trial, so a step costs O(m t), not O(m t^2)):
        n, cap = len(self.prior), self.config.max_trials
        self._k_sx = np.empty((n, cap))  # kernel between every candidate and each trial
        self._v = np.empty((cap, n))  # L^-1 k_xs, rows fixed once computed
        self._chol = np.zeros((cap, cap))  # Cholesky factor of K_xx + noise I

    # -- the model --------------------------------------------------------------------------
    @property
    def mean(self) -> np.ndarray:
        """Posterior mean speed of every candidate [m/s]."""
        return self._mu

    @property
    def std(self) -> np.ndarray:
        """Posterior standard deviation of every candidate [m/s]."""
        return np.sqrt(np.maximum(self._var, 0.0))

    def _prior_variance(self) -> float:
        """Return a gait's prior variance under the broad kernel [(m/s)^2]."""
        return self.config.signal_variance + self.config.offset_std**2

    def _refit(self) -> None:
        """
        Add the newest trial to the posterior: kernel column, Cholesky row, v row.

        Then the mean from all observations. Same GP as a full refit (Matern 5/2, explicit noise).
        Matrix-vector work this small is slower on several BLAS threads when the cores are busy (24
        ms instead of 1.5 ms measured with a simulator beside it), so it runs on one.
        """
        with threadpool_limits(limits=1, user_api='blas'):
            self._add_last_trial()

    def _add_last_trial(self) -> None:
        t = len(self.trials) - 1
        new = self.trials[-1]
        x = self.descriptors[new.index][None, :]
        s2, c2 = self.config.signal_variance, self.config.offset_std**2
        k_new = s2 * matern52(self.descriptors, x, self.config.length_scale)[:, 0]  # (m,)
        if c2:
            k_new = k_new + c2
        self._k_sx[:, t] = k_new
        idx = np.array([tr.index for tr in self.trials])
        chol = self._chol
        if t == 0:
            chol[0, 0] = math.sqrt(s2 + c2 + self.config.noise)
            row = np.empty(0)
        else:
            row = _solve_lower(chol[:t, :t], k_new[idx[:t]])  # L^-1 k(x_old, x_new)
            chol[t, :t] = row
            chol[t, t] = math.sqrt(max(s2 + c2 + self.config.noise - float(row @ row), 1e-12))
        self._v[t] = (k_new - row @ self._v[:t]) / chol[t, t]
        self._gp_var = self._gp_var - self._v[t] ** 2
        lower = chol[: t + 1, : t + 1]
        measured = np.array([tr.measured for tr in self.trials])[:, None]
        broad = slice(self._known, None)  # the hypotheses under this kernel (all, or 'unknown')
        y = measured - self._means[broad][:, idx].T
        white = solve_triangular(lower, y, lower=True, check_finite=False)  # (t+1, h)
        alpha = solve_triangular(lower.T, white, lower=False, check_finite=False)
        k_sx = self._k_sx[:, : t + 1]  # one product per hypothesis: bit-identical to the thesis's
        self._mu_h[broad] = self._means[broad] + np.stack(
            [k_sx @ alpha[:, h] for h in range(alpha.shape[1])]
        )
        self._log_weight[broad] = -0.5 * np.sum(white * white, axis=0)
        if self._known:
            self._log_weight[broad] -= np.sum(np.log(np.diag(lower)))
            self._refit_known(idx, measured - self._means[: self._known][:, idx].T)
        self._mix()

    def _refit_known(self, idx: np.ndarray, y: np.ndarray) -> None:
        """
        Redo the known models under their tight kernel (a full refit: a few dozen trials).

        Two kernels compete, so each likelihood carries its kernel's determinant. ``y``: the
        trials' residuals under each known model (t, k).
        """
        k = self._known
        c = self.config
        unit = matern52(self.descriptors, self.descriptors[idx], c.length_scale)  # (m, t)
        a = c.known_std**2 * unit[idx] + c.noise * np.eye(len(idx))
        chol = np.linalg.cholesky(a)
        white = solve_triangular(chol, y, lower=True, check_finite=False)
        alpha = solve_triangular(chol.T, white, lower=False, check_finite=False)
        k_sx = c.known_std**2 * unit
        self._mu_h[:k] = self._means[:k] + (k_sx @ alpha).T
        self._log_weight[:k] = -0.5 * np.sum(white * white, axis=0) - np.sum(np.log(np.diag(chol)))
        v = solve_triangular(chol, k_sx.T, lower=True, check_finite=False)
        self._known_var = np.maximum(c.known_std**2 - np.sum(v * v, axis=0), 0.0)

    def _mix(self) -> None:
        log_weight = self._log_weight + self._log_prior
        if not self._known:  # one kernel: the thesis's GP when there are no hypotheses
            self._weights, self._mu, self._var = mixture(log_weight, self._mu_h, self._gp_var)
            return
        var_h = np.repeat(self._gp_var[None], len(self._means), axis=0)
        var_h[: self._known] = self._known_var
        self._weights, self._mu, self._var = mixture(log_weight, self._mu_h, var_h)

    @property
    def hypothesis_means(self) -> np.ndarray:
        """Posterior mean speed of every candidate under each hypothesis (h, m) [m/s]."""
        return self._mu_h

    @property
    def weights(self) -> np.ndarray:
        """
        Weight of each hypothesis: the map's prior first, then ``hypotheses`` in order.

        With ``config.known_std`` > 0, 'unknown damage' comes last.
        """
        return self._weights

    # -- the loop ---------------------------------------------------------------------------
    def tested(self) -> set[int]:
        """Candidate indices tried so far."""
        return {t.index for t in self.trials}

    def excluded(self) -> set[int]:
        """
        Return the candidates not to try (again).

        The tested (``exclude_tested``), the tipped and the vetoed.
        """
        tried = (
            self.tested()
            if self.config.exclude_tested
            else {t.index for t in self.trials if t.tipped}
        )
        return tried | self.vetoed

    def veto(self, index: int) -> None:
        """
        Never try candidate ``index``, e.g. a gait that tips in a simulation of the damage.

        It also leaves alpha's bar (:meth:`leading_index`): a gait the run may not try is not a
        speed it could reach.
        """
        if not 0 <= index < len(self.prior):
            raise ValueError(f'candidate {index} does not exist (0..{len(self.prior) - 1})')
        self.vetoed.add(int(index))

    def leading_index(self) -> int | None:
        """
        Return the candidate with the highest posterior mean that is not vetoed (None: none left).

        Its mean sets alpha's bar (:meth:`alpha_met`).
        """
        if not self.vetoed:
            return int(np.argmax(self._mu))
        if len(self.vetoed) == len(self.prior):
            return None
        mu = self._mu.copy()
        mu[list(self.vetoed)] = -np.inf
        return int(np.argmax(mu))

    def _bar(self) -> float:
        """Return the highest mean alpha is measured against [m/s] (0: every gait vetoed)."""
        lead = self.leading_index()
        return 0.0 if lead is None else float(self._mu[lead])

    def best(self) -> Trial | None:
        """
        Return the trial with the highest measured speed (None before the first).

        A tipped trial is never the best, whatever its score: the run leaves its best gait on
        the robot. None when every trial tipped.
        """
        upright = [t for t in self.trials if not t.tipped]
        return max(upright, key=lambda t: t.measured) if upright else None

    def stop_reason(self) -> StopReason:
        """Why the run should stop now (``StopReason.CONTINUE`` if it should not)."""
        if len(self.trials) >= self.config.max_trials:
            return StopReason.MAX_TRIALS
        gain = self.config.stop_gain
        if self.alpha_met() and (gain is None or self.max_expected_gain() < gain):
            return StopReason.ALPHA_REACHED
        if len(self.excluded()) == len(self.prior):
            return StopReason.MAP_EXHAUSTED
        return StopReason.CONTINUE

    def alpha_met(self) -> bool:
        """
        Whether the best gait meets M-BOA's success rule: alpha x the highest mean, and the floor.

        The highest mean of a gait the run may try: vetoed gaits do not count.

        The run's success. It stops there unless the expected-gain stop keeps it going, or the
        budget ends it first.
        """
        best = self.best()
        return (
            best is not None
            and best.measured >= self.config.alpha * self._bar()
            and best.measured >= self.config.min_speed
        )

    def should_stop(self) -> tuple[bool, str]:
        """(stop, why) with ``why`` a sentence for people (decide on :meth:`stop_reason`)."""
        reason = self.stop_reason()
        floor = self._below_floor()
        if reason is StopReason.MAX_TRIALS:
            best = self.best()
            said = f'; best measured {best.measured:.3f} m/s' if best is not None else ''
            met = f" (M-BOA's rule met: {self._alpha_clause()})" if self.alpha_met() else ''
            return True, f'budget used: {self.config.max_trials} trials{said}{met}{floor}'
        if reason is StopReason.ALPHA_REACHED:
            return True, f'gait found: {self._alpha_clause()}{floor}'

        if reason is StopReason.MAP_EXHAUSTED:
            skipped = f' or vetoed ({len(self.vetoed)})' if self.vetoed else ''
            return True, f'every gait in the map has been tried{skipped}{floor}'
        return False, ''

    def _alpha_clause(self) -> str:
        """Say how the best gait meets alpha (call only when it has one)."""
        best = self.best()
        assert best is not None
        return (
            f'best measured {best.measured:.3f} m/s >= alpha x max predicted '
            f'({self.config.alpha:g} x {self._bar():.3f} m/s)'
        )

    def _below_floor(self) -> str:
        best = self.best()
        if best is None or best.measured >= self.config.min_speed:
            return ''
        return (
            f'; the best gait walked {best.measured:.3f} m/s, below the success floor'
            f' {self.config.min_speed:.3f} m/s'
        )

    def expected_gain(self) -> np.ndarray:
        """
        Return the expected improvement over the best measured speed of each candidate [m/s].

        E[max(f(x) - best, 0)] under the posterior; 0 for tried candidates (when excluded) and
        the posterior mean's excess before the first trial is measured against 0.
        """
        best = self.best()
        level = best.measured if best is not None else 0.0
        std = self.std
        excess = self._mu - level
        with np.errstate(divide='ignore', invalid='ignore'):
            z = np.where(std > 0, excess / np.where(std > 0, std, 1.0), 0.0)
        gain = np.where(std > 0, excess * ndtr(z) + std * np.exp(-0.5 * z * z) / SQRT_2PI, 0.0)
        gain = np.maximum(gain, np.maximum(excess, 0.0) * (std <= 0))
        excluded = self.excluded()
        if excluded:
            gain[list(excluded)] = 0.0
        return gain

    def max_expected_gain(self) -> float:
        """Return the highest expected improvement of one more trial [m/s]."""
        return float(np.max(self.expected_gain()))

    def next_index(self) -> int:
        """Return the candidate with the highest UCB (untested ones only, by default)."""
        ucb = self._mu + self.config.kappa * self.std
        excluded = self.excluded()
        if excluded:
            ucb = ucb.copy()
            ucb[list(excluded)] = -np.inf
        return int(np.argmax(ucb))

    def observe(self, index: int, measured: float, tipped: bool = False) -> Trial:
        """
        Record a trial of candidate ``index`` that walked at ``measured`` m/s.

        ``tipped``: the tip guard stopped it; it is never tried again, whatever
        ``exclude_tested`` says.
        """
        if not 0 <= index < len(self.prior):
            raise ValueError(f'candidate {index} does not exist (0..{len(self.prior) - 1})')
        if not math.isfinite(measured):
            raise ValueError(f'measured speed must be finite, got {measured!r}')
        if len(self.trials) >= self.config.max_trials:
            raise RuntimeError(f'already {len(self.trials)} trials, the maximum')
        trial = Trial(
            len(self.trials) + 1,
            index,
            float(self.prior[index]),
            float(self._mu[index]),
            float(self.std[index]),
            float(measured),
            bool(tipped),
        )
        self.trials.append(trial)
        self._refit()
        return trial
