"""Map-based Bayesian optimisation, M-BOA (thesis algorithm 2, Cully et al. 2015); ROS-free.

A Gaussian process over the behaviour descriptors of the map's elites models the real speed
of each elite. Its prior mean is the speed the map predicts (simulation, intact robot); the
kernel is Matern 5/2 with length scale rho and unit signal variance; observations carry noise
variance ``noise`` (0.001 in the papers -- set explicitly, never a library default).

    next trial  = argmax_x  mu_t(x) + kappa * sigma_t(x)            (UCB, sigma = std dev)
    stop when   max measured >= alpha * max_x mu_t(x), or after max_trials trials

An elite already tried is not offered again: the next-best untried elite is (re-testing the
same gait would only average its noise; see ``MboaConfig.exclude_tested``).
Speeds are in m/s throughout.
"""
from __future__ import annotations

import enum

import math
from dataclasses import dataclass, field

import numpy as np


class StopReason(enum.Enum):
    """Why an M-BOA run stops (thesis 5.2.2's stopping rule, the trial budget, or a used-up map)."""

    CONTINUE = "continue"
    ALPHA_REACHED = "alpha_reached"   # best measured >= alpha x highest posterior mean: success
    MAX_TRIALS = "max_trials"
    MAP_EXHAUSTED = "map_exhausted"


@dataclass(frozen=True)
class MboaConfig:
    max_trials: int = 20
    alpha: float = 0.90          # stop ratio
    kappa: float = 0.05          # UCB exploration weight (times the standard deviation)
    length_scale: float = 0.4    # rho, in descriptor units (duty factor, 0..1)
    noise: float = 0.001         # observation noise variance [(m/s)^2]
    exclude_tested: bool = True

    def __post_init__(self) -> None:
        problems = []
        if not (isinstance(self.max_trials, int) and self.max_trials >= 1):
            problems.append(f"max_trials must be an integer >= 1 (got {self.max_trials!r})")
        if not (math.isfinite(self.alpha) and 0.0 < self.alpha <= 1.0):
            problems.append(f"alpha (stop ratio) must be in (0, 1] (got {self.alpha!r})")
        if not (math.isfinite(self.kappa) and self.kappa >= 0.0):
            problems.append(f"kappa must be >= 0 (got {self.kappa!r})")
        if not (math.isfinite(self.length_scale) and self.length_scale > 0.0):
            problems.append(f"length_scale (rho) must be > 0 (got {self.length_scale!r})")
        if not (math.isfinite(self.noise) and self.noise > 0.0):
            problems.append(f"noise variance must be > 0 (got {self.noise!r})")
        if problems:
            raise ValueError("; ".join(problems))


def matern52(a: np.ndarray, b: np.ndarray, length_scale: float) -> np.ndarray:
    """Matern 5/2 kernel matrix between rows of a (n, d) and b (m, d), unit variance."""
    d = np.sqrt(np.maximum(((a[:, None, :] - b[None, :, :]) ** 2).sum(-1), 0.0)) / length_scale
    s5d = math.sqrt(5.0) * d
    return (1.0 + s5d + 5.0 / 3.0 * d * d) * np.exp(-s5d)


@dataclass
class Trial:
    number: int            # 1-based
    index: int             # candidate index (row of the descriptors given to Mboa)
    predicted: float       # map prior at that elite [m/s]
    gp_mean: float         # posterior mean before the trial [m/s]
    gp_std: float
    measured: float        # [m/s]


@dataclass
class Mboa:
    """M-BOA over ``descriptors`` (m, 6) with prior speeds ``prior`` (m,)."""

    descriptors: np.ndarray
    prior: np.ndarray
    config: MboaConfig = field(default_factory=MboaConfig)
    trials: list[Trial] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.descriptors = np.atleast_2d(np.asarray(self.descriptors, dtype=float))
        self.prior = np.asarray(self.prior, dtype=float)
        if len(self.descriptors) == 0 or self.prior.shape != (len(self.descriptors),):
            raise ValueError(f"need one prior speed per descriptor, got {self.prior.shape} for "
                             f"{len(self.descriptors)} descriptors")
        if not (np.all(np.isfinite(self.descriptors)) and np.all(np.isfinite(self.prior))):
            raise ValueError("descriptors and prior speeds must be finite (pass only filled niches)")
        self._mu = self.prior.copy()
        self._var = np.ones(len(self.prior))

    # -- the model --------------------------------------------------------------------------
    @property
    def mean(self) -> np.ndarray:
        return self._mu

    @property
    def std(self) -> np.ndarray:
        return np.sqrt(np.maximum(self._var, 0.0))

    def _refit(self) -> None:
        idx = np.array([t.index for t in self.trials])
        y = np.array([t.measured for t in self.trials])
        x = self.descriptors[idx]
        k_xx = matern52(x, x, self.config.length_scale) + self.config.noise * np.eye(len(idx))
        chol = np.linalg.cholesky(k_xx)
        k_sx = matern52(self.descriptors, x, self.config.length_scale)          # (m, t)
        alpha = np.linalg.solve(chol.T, np.linalg.solve(chol, y - self.prior[idx]))
        self._mu = self.prior + k_sx @ alpha
        v = np.linalg.solve(chol, k_sx.T)                                        # (t, m)
        self._var = 1.0 - np.sum(v * v, axis=0)

    # -- the loop ---------------------------------------------------------------------------
    def tested(self) -> set[int]:
        return {t.index for t in self.trials}

    def best(self) -> Trial | None:
        return max(self.trials, key=lambda t: t.measured) if self.trials else None

    def stop_reason(self) -> StopReason:
        """Why the run should stop now (``StopReason.CONTINUE`` if it should not)."""
        if len(self.trials) >= self.config.max_trials:
            return StopReason.MAX_TRIALS
        best = self.best()
        if best is not None and best.measured >= self.config.alpha * float(np.max(self._mu)):
            return StopReason.ALPHA_REACHED
        if self.config.exclude_tested and len(self.tested()) == len(self.prior):
            return StopReason.MAP_EXHAUSTED
        return StopReason.CONTINUE

    def should_stop(self) -> tuple[bool, str]:
        """(stop, why) with ``why`` a sentence for people (decide on :meth:`stop_reason`)."""
        reason = self.stop_reason()
        if reason is StopReason.MAX_TRIALS:
            return True, f"reached the maximum of {self.config.max_trials} trials"
        if reason is StopReason.ALPHA_REACHED:
            best = self.best()
            assert best is not None
            return True, (f"best measured {best.measured:.3f} m/s >= alpha x max predicted "
                          f"({self.config.alpha:g} x {np.max(self._mu):.3f} m/s)")
        if reason is StopReason.MAP_EXHAUSTED:
            return True, "every gait in the map has been tried"
        return False, ""

    def next_index(self) -> int:
        """The candidate with the highest UCB (untested ones only, by default)."""
        ucb = self._mu + self.config.kappa * self.std
        if self.config.exclude_tested and self.trials:
            ucb = ucb.copy()
            ucb[list(self.tested())] = -np.inf
        return int(np.argmax(ucb))

    def observe(self, index: int, measured: float) -> Trial:
        """Record a trial of candidate ``index`` that walked at ``measured`` m/s."""
        if not 0 <= index < len(self.prior):
            raise ValueError(f"candidate {index} does not exist (0..{len(self.prior) - 1})")
        if not math.isfinite(measured):
            raise ValueError(f"measured speed must be finite, got {measured!r}")
        if len(self.trials) >= self.config.max_trials:
            raise RuntimeError(f"already {len(self.trials)} trials, the maximum")
        trial = Trial(len(self.trials) + 1, index, float(self.prior[index]), float(self._mu[index]),
                      float(self.std[index]), float(measured))
        self.trials.append(trial)
        self._refit()
        return trial
