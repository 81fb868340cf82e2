# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The learned correction of the repertoire's steps under damage (ROS-free).

:class:`CorrectionGP`: one Gaussian process per displacement dimension (x, y, heading) over the
repertoire's descriptor, learning from every step how the damage changes the steps, and weighing
the damage bank's hypotheses (:mod:`hexapod_navigation.core.step_bank`) by how well they explain
the steps and tripod cycles walked. The planner (:mod:`hexapod_navigation.core.planner`) plans on
its predictions.
"""

from __future__ import annotations

from typing import Sequence

from hexapod_adapt import mixture, REACH
from hexapod_navigation.core.config import NavigationConfig
from hexapod_navigation.core.repertoire import Repertoire
import numpy as np
from scipy.linalg import solve_triangular


class CorrectionGP:
    """
    Learned change of every repertoire step under damage: one GP per dimension (x, y, heading).

    Inputs are the repertoire's descriptors (each step's intact displacement); the prior mean is
    the intact step itself (heading change 0), so with no data the prediction is the repertoire.
    The kernel is a squared exponential (local changes) plus a linear kernel on the intact
    displacement (a change common to every step, e.g. all steps shorter or turned: learned from
    a few steps for the whole repertoire). Hyperparameters from NavigationConfig.

    ``hypotheses`` (h, n, 3), optional: other prior means, e.g. the steps re-measured under each
    one- and two-leg failure (:mod:`hexapod_navigation.core.step_bank`). Each, the intact
    repertoire among them, is weighted by its prior (``config.prior_intact``) times its marginal
    likelihood over the steps walked (the three dimensions' GPs together), and predictions are the
    mixture (as in :class:`hexapod_adapt.online.mboa.Mboa`).

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
