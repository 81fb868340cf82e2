# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A blind run's safety model: each gait's risk of tipping the robot, before it is tried.

Issue 67, deliverable 2. A blind run does not know its damage, so no re-score says which gaits
tip. What it knows about a gait:

- how far it tilts the body walked under each damage hypothesis on the map's engine (the
  diagnosis's walks, shared with it), and walked intact for "none of these";
- how much each hypothesis is believed (the diagnosis's posterior; before any trial, its prior);
- the trials so far: each trial's peak tilt against the tilt the weighed walks predicted for it.
  The differences (the damage and the physics the walks lack) are smoothed over the descriptor
  space by a Gaussian process with M-BOA's kernel plus a constant, so a trial that tilted more
  than predicted raises its neighbours' predicted tilt most (SafeAPT's safety model over the
  behaviour space) and every gait's a little.

A gait's risk is the believed probability that its trial tilts past the tip guard::

    risk(g) = sum_h p(h) Phi((tilt_h(g) + r(g) - guard) / sqrt(spread^2 + s(g)^2))

with ``r``, ``s`` the GP's mean and standard deviation at g and ``spread`` how far a trial's
peak tilt lies from its simulated walk's. A gait whose risk exceeds the limit is never tried.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import math
from typing import Callable, Sequence

from hexapod_adapt.online.diagnosis import TrialRecord
from hexapod_adapt.online.mboa import matern52
from hexapod_sim.simulator import TIP_OVER_DEG
import numpy as np
from scipy.special import ndtr

#: Risk above which a gait is not tried (a belief of 1 in 4 that it tips).
RISK_LIMIT = 0.25
#: [rad] spread of a trial's peak tilt around its simulated walk's (about 6 deg: what another
#: physics moves a walk's tilt by; judgement, as the diagnosis's noise scales).
TILT_SPREAD = 0.1
#: [rad] how far the trials may move the tilts the walks predict near a trial (the GP's local
#: standard deviation), and everywhere at once (a constant term: a damage the walks lack tilts
#: every gait more, and each trial says how much; 0 until the tuning set chooses it:
#: studies/diagnosis/README.md).
TILT_SHIFT = 0.15
TILT_OFFSET = 0.0
#: Descriptor units: the GP's length scale, M-BOA's default profile's.
TILT_LENGTH_SCALE = 0.3
#: A hypothesis believed less than this is left out of a gait's risk (and not walked for it).
NEGLIGIBLE_WEIGHT = 1e-9
#: A hypothesis believed at least this much tilts as its ``kin`` walk says (its worst kin), the
#: others as their own walk: one believed less adds under 0.05 to a risk (judgement, before its
#: runs: studies/diagnosis/README.md, "The safety model's lifted bank stands in for five kinds").
KIN_WEIGHT = 0.05
#: [rad] what a trial the tip guard stopped counts as: the tip-over line.
TIPPED_TILT = math.radians(TIP_OVER_DEG)

#: Walk gait ``niche`` under hypothesis ``h`` (h = the number of hypotheses: intact, for "none
#: of these"); None: it cannot be walked.
WalkOf = Callable[[int, int], 'TrialRecord | None']
#: Walk gait ``niche`` ahead, under the hypotheses ``own`` (as ``walk``) and ``kin`` (as ``kin``),
#: so that the walks asked for one at a time after it are made (in several processes) at once.
PrefetchOf = Callable[[int, Sequence[int], Sequence[int]], None]


def record_tilt(record: TrialRecord | None) -> float:
    """Return a walk's largest |roll| or |pitch| [rad] (pi: it cannot be walked, it may tip)."""
    if record is None:
        return math.pi
    return float(np.max(np.abs(record.attitude[:, :2]), initial=0.0))


@dataclass
class SafetyModel:
    """
    Each candidate gait's risk of tipping past ``guard``, updated by the trials.

    ``niches`` and ``descriptors`` are M-BOA's candidates (``candidates(archive)``); ``walk``
    gives their walks under the ``hypotheses`` damage hypotheses and intact (index
    ``hypotheses``). ``weights`` is the belief over the hypotheses and "none of these" (last).
    ``kin``: a hypothesis believed at least ``kin_weight`` tilts as the most tilted of its walk
    and its ``kin`` walk (the damages it stands in for; None: its walk alone). ``prefetch``:
    makes a gait's missing walks at once before they are asked for (None: one by one).
    """

    niches: np.ndarray
    descriptors: np.ndarray
    walk: WalkOf
    hypotheses: int
    guard: float
    weights: np.ndarray
    limit: float = RISK_LIMIT
    spread: float = TILT_SPREAD
    shift: float = TILT_SHIFT
    offset: float = TILT_OFFSET
    length_scale: float = TILT_LENGTH_SCALE
    kin: WalkOf | None = None
    kin_weight: float = KIN_WEIGHT
    prefetch: PrefetchOf | None = None
    tilts: dict[int, float] = field(default_factory=dict)  # index -> predicted tilt [rad]
    risks: dict[int, float] = field(default_factory=dict)  # index -> risk when last asked
    _seen: list[tuple[int, float]] = field(default_factory=list)  # (index, residual [rad])
    _walked: dict[int, np.ndarray] = field(default_factory=dict)
    _kin_walked: dict[int, np.ndarray] = field(default_factory=dict)
    _fit: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None  # (x, chol, alpha) of _seen

    def __post_init__(self) -> None:
        weights = np.asarray(self.weights, dtype=float)
        if weights.shape != (self.hypotheses + 1,) or not np.isclose(weights.sum(), 1.0):
            raise ValueError(
                f'weights must be {self.hypotheses + 1} probabilities (the hypotheses and none)'
            )
        if not 0.0 <= self.kin_weight <= 1.0:
            raise ValueError(f'kin_weight must lie in [0, 1], got {self.kin_weight}')
        if not 0.0 < self.limit < 1.0:
            raise ValueError(f'the risk limit must lie in (0, 1), got {self.limit}')
        if not (
            self.spread > 0 and self.shift >= 0 and self.offset >= 0 and self.length_scale > 0
        ):
            raise ValueError('spread and length_scale must be positive, shift and offset not')
        self.weights = weights

    def weigh(self, probabilities: np.ndarray) -> None:
        """Take the diagnosis's posterior (the hypotheses and none, last) as the belief."""
        self.weights = np.asarray(probabilities, dtype=float)

    def simulated(self, index: int) -> np.ndarray:
        """
        Return candidate ``index``'s simulated peak tilt under each hypothesis and intact.

        Only those in play are walked (believed at least :data:`NEGLIGIBLE_WEIGHT`); nan for
        the others, until the belief brings them back.
        """
        tilts = self._walked.get(int(index))
        if tilts is None:
            tilts = self._walked[int(index)] = np.full(self.hypotheses + 1, np.nan)
        niche = int(self.niches[index])
        own = np.flatnonzero((self.weights >= NEGLIGIBLE_WEIGHT) & np.isnan(tilts))
        kin = wary = None
        kin_missing: np.ndarray = np.zeros(0, dtype=int)
        if self.kin is not None:
            kin = self._kin_walked.get(int(index))
            if kin is None:
                kin = self._kin_walked[int(index)] = np.full(self.hypotheses + 1, np.nan)
            wary = self.weights >= max(self.kin_weight, NEGLIGIBLE_WEIGHT)
            kin_missing = np.flatnonzero(wary & np.isnan(kin))
        if self.prefetch is not None:  # (it leaves a lone walk to the loops below)
            self.prefetch(niche, own.tolist(), kin_missing.tolist())
        for h in own:
            tilts[h] = record_tilt(self.walk(niche, int(h)))
        if self.kin is None:
            return tilts
        for h in kin_missing:
            kin[h] = record_tilt(self.kin(niche, int(h)))
        return np.where(wary, np.fmax(tilts, kin), tilts)

    def predicted(self, index: int) -> float:
        """Return the tilt [rad] the belief and the trials predict for candidate ``index``."""
        mean, _ = self._residual(index)
        return self._weighed(self.simulated(index)) + mean

    def risk(self, index: int) -> float:
        """Return the believed probability that candidate ``index`` tilts past the guard."""
        mean, std = self._residual(index)
        z = (self.simulated(index) + mean - self.guard) / math.hypot(self.spread, std)
        return self._weighed(ndtr(z))

    def _weighed(self, values: np.ndarray) -> float:
        """Return the belief's mean of per-hypothesis ``values`` over those in play."""
        play = self.weights >= NEGLIGIBLE_WEIGHT
        return float(self.weights[play] @ values[play])

    def tips(self, index: int) -> bool:
        """Whether candidate ``index`` is too risky to try (a session's screen asks this)."""
        index = int(index)
        self.risks[index] = self.risk(index)
        self.tilts[index] = self.predicted(index)
        return self.risks[index] > self.limit

    def observe(self, index: int, peak_tilt: float, tipped: bool) -> None:
        """
        Take a trial's peak tilt [rad] (before the posterior moves on its record).

        A trial the guard stopped counts as one that went on to the tip-over line (the guard
        stops it there because it was falling); a tilt not measured (nan, a robot with no IMU)
        teaches nothing unless the trial tipped.
        """
        seen = TIPPED_TILT if tipped else float(peak_tilt)
        if math.isfinite(seen):
            expected = self._weighed(self.simulated(int(index)))
            self._seen.append((int(index), seen - expected))
            self._fit = None  # refit on the next question

    def _residual(self, index: int) -> tuple[float, float]:
        """Return the GP's mean and standard deviation [rad] of the tilt residual at ``index``."""
        prior = self.shift**2 + self.offset**2
        if not self._seen or prior == 0:
            return 0.0, math.sqrt(prior)
        if self._fit is None:  # once per trial, not per gait asked about
            x = self.descriptors[np.array([i for i, _ in self._seen])]
            y = np.array([r for _, r in self._seen])
            k = self.shift**2 * matern52(x, x, self.length_scale) + self.offset**2
            k[np.diag_indices_from(k)] += self.spread**2
            chol = np.linalg.cholesky(k)
            self._fit = (x, chol, np.linalg.solve(chol.T, np.linalg.solve(chol, y)))
        x, chol, alpha = self._fit
        near = matern52(self.descriptors[[index]], x, self.length_scale)[0]
        ks = self.shift**2 * near + self.offset**2
        v = np.linalg.solve(chol, ks)
        return float(ks @ alpha), math.sqrt(max(prior - float(v @ v), 0.0))
