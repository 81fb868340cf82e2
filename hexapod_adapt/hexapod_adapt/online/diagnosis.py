# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Name the damage from the trials: a posterior over damage hypotheses, trial by trial.

Each trial is a :class:`TrialRecord`, plain data any trial source can fill (a simulator's walk,
the bridge's IMU and odometry, a recording replayed): time stamps, the body's position and
attitude, and the foot contacts where they are known. Its :func:`signature` is what a damage
changes in a walk: the speed along the walking direction, the drift across it, the yaw rate,
the mean roll and pitch, how roll and pitch move through the gait cycle (a lifted leg tilts the
body toward its corner in the phase that leg would have carried it), and each foot's duty
factor.

:class:`Diagnosis` compares each trial's signature with the same gait simulated under each
hypothesis (on the map's engine; each walk simulated when first needed, then kept) and keeps a
posterior over the hypotheses plus "none of these". A feature's mismatch is scaled by its noise
(:data:`FEATURE_NOISE`) and weighed with a Student-t (a few features far off, as another physics
gives them, do not veto a hypothesis the others support); "none of these" explains every trial
equally, as a hypothesis ``none_deviation`` noise scales off in every feature would; each
trial's likelihood is raised to a ``temperature`` (:class:`Weighing`). A :class:`GapCalibration`,
measured on the intact robot (:func:`calibrate_gap`), takes the robot's own bias out of every
comparison.
"""

from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass, field
import math
from typing import Callable, Iterable, Iterator, Sequence

from hexapod_adapt.mapping.archive import Archive
from hexapod_adapt.mapping.simulation import engine_of_map, trial_substeps, worker_simulator
from hexapod_description import N_LEGS
from hexapod_sim.damage import Damage
from hexapod_sim.simulator import quat_to_euler
from hexapod_sim.traces import GaitTrace, trace_gait
from hexapod_util.processes import map_in_workers, Stopped
import numpy as np
from scipy.special import logsumexp

#: Gait-cycle phase bins of the roll and pitch profile.
PHASE_BINS = 4
#: [s] the start of a walk left out of the signature (the body settles from standing).
SETTLE_S = 1.0
#: The noise scale of each feature group: how far a trial's feature may lie from the same gait
#: simulated under the true damage (another physics, the robot's sensors). Units: m/s, rad/s,
#: rad, duty fraction.
FEATURE_NOISE = {
    'speed': 0.04,
    'drift': 0.04,
    'yaw_rate': 0.06,
    'roll': 0.03,
    'pitch': 0.03,
    'roll_phase': 0.015,
    'pitch_phase': 0.015,
    'duty': 0.15,
}
#: Student-t degrees of freedom of a feature's mismatch.
STUDENT_NU = 4.0
#: A hypothesis this many nats below the most probable (a probability ratio under 1e-10) is
#: asleep: a trial's gait is not walked under it. Its log posterior is kept as an upper bound (a
#: trial's log likelihood is at most 0), and tightened by the gaits it missed, one at a time,
#: whenever the bound comes within this of the most probable again.
ASLEEP_NATS = 23.0
NONE_LABEL = 'none of these'
#: The mean log likelihood per trial below which a hypothesis does not fit (:class:`Weighing`),
#: in the first bank and in the wider one (studies/diagnosis/README.md, "Does the leader fit?"
#: and "The servo's range as a tuning set").
FIT_FLOOR = -12.0
WIDER_FIT_FLOOR = -20.0


@dataclass(frozen=True)
class Weighing:
    """
    How a trial weighs the hypotheses.

    ``none_deviation``: "none of these" explains a trial as a hypothesis this many noise scales
    off in every feature would; ``none_prior``: its prior probability; ``temperature``: each
    trial's log likelihood is multiplied by it (below 1: the features are not independent
    witnesses, and one trial should not be worth their product). The defaults won on a tuning
    set (studies/diagnosis/README.md, "How sure the diagnosis should be"). ``fit_floor``: a
    hypothesis whose mean log likelihood over the trials lies below it does not fit, however
    probable, and is not named (None: every one fits; the default won on a tuning set:
    studies/diagnosis/README.md, "Does the leader fit?"); ``wider_fit_floor``: the fit floor
    of the wider bank a run goes on to once none of its first bank's fits (``wider`` of
    :func:`~hexapod_adapt.online.session.diagnosis_plan`; lower: its leader is the best of 8
    kinds). ``wake_walks``: the most walks a trial's waking of asleep hypotheses may simulate
    (None: no cap; the default is a compute budget, about 6 s of a core:
    studies/diagnosis/README.md, "A trial's cost in walks").
    """

    none_deviation: float = 2.5
    none_prior: float = 0.2
    temperature: float = 1.0
    fit_floor: float | None = FIT_FLOOR
    wider_fit_floor: float | None = WIDER_FIT_FLOOR
    wake_walks: int | None = 60

    def __post_init__(self) -> None:
        if not 0.0 < self.none_prior < 1.0:
            raise ValueError(f'none_prior must lie in (0, 1), got {self.none_prior}')
        if not (math.isfinite(self.none_deviation) and self.none_deviation > 0):
            raise ValueError(f'none_deviation must be > 0, got {self.none_deviation}')
        if not (math.isfinite(self.temperature) and 0.0 < self.temperature <= 1.0):
            raise ValueError(f'temperature must lie in (0, 1], got {self.temperature}')
        for name in ('fit_floor', 'wider_fit_floor'):
            floor = getattr(self, name)
            if floor is not None and not (math.isfinite(floor) and floor < 0):
                raise ValueError(f'{name} must be a negative log likelihood, got {floor}')
        if self.wake_walks is not None and (
            isinstance(self.wake_walks, bool)
            or not isinstance(self.wake_walks, int)
            or self.wake_walks < 1
        ):
            raise ValueError(f'wake_walks must be a whole number >= 1, got {self.wake_walks!r}')


@dataclass(frozen=True)
class TrialRecord:
    """
    What one trial recorded, as plain data.

    ``t`` (n,) s since the gait began (its phase 0); ``position`` (n, 2 or 3) m and ``attitude``
    (n, 3) roll, pitch, yaw [rad] of the body in a fixed frame (odom); ``crab`` [rad] the
    walking direction in the body frame; ``period`` [s] the gait's cycle; ``contacts`` (n, 6)
    whether each foot touched since the previous sample (None: not measured, as on the robot).
    """

    t: np.ndarray
    position: np.ndarray
    attitude: np.ndarray
    crab: float
    period: float
    contacts: np.ndarray | None = None

    def __post_init__(self) -> None:
        t = np.asarray(self.t, dtype=float)
        n = len(t)
        if n < 2 or not np.isfinite(t).all() or np.any(np.diff(t) <= 0):
            raise ValueError('a trial record needs 2 or more finite, increasing time stamps')
        position = np.asarray(self.position, dtype=float)
        if position.ndim != 2 or position.shape[0] != n or position.shape[1] not in (2, 3):
            raise ValueError(f'position must be ({n}, 2) or ({n}, 3), got {position.shape}')
        attitude = np.asarray(self.attitude, dtype=float)
        if attitude.shape != (n, 3):
            raise ValueError(f'attitude must be ({n}, 3) roll, pitch, yaw, got {attitude.shape}')
        if not (np.isfinite(position).all() and np.isfinite(attitude).all()):
            raise ValueError('position and attitude must be finite')
        if not (math.isfinite(self.crab) and math.isfinite(self.period) and self.period > 0):
            raise ValueError(
                f'crab and period must be finite, period > 0: {self.crab}, {self.period}'
            )
        contacts = self.contacts
        if contacts is not None:
            contacts = np.asarray(contacts, dtype=bool)
            if contacts.shape != (n, N_LEGS):
                raise ValueError(f'contacts must be ({n}, {N_LEGS}), got {contacts.shape}')
        for name, value in (('t', t), ('position', position), ('attitude', attitude)):
            object.__setattr__(self, name, value)
        object.__setattr__(self, 'contacts', contacts)

    @classmethod
    def from_trace(cls, trace: GaitTrace, contacts: bool = True) -> TrialRecord:
        """Return the record of a simulated walk (``contacts``: keep its foot contacts)."""
        attitude = np.array([quat_to_euler(q) for q in trace.quaternion])
        return cls(
            trace.t,
            trace.position,
            attitude,
            float(trace.gait.crab_angle),
            float(trace.gait.period),
            trace.contacts if contacts else None,
        )


def feature_names(contacts: bool) -> tuple[str, ...]:
    """Return the names of a signature's features, in order."""
    names = ['speed', 'drift', 'yaw_rate', 'roll', 'pitch']
    names += [f'roll_phase_{b}' for b in range(PHASE_BINS)]
    names += [f'pitch_phase_{b}' for b in range(PHASE_BINS)]
    if contacts:
        names += [f'duty_{leg}' for leg in range(1, N_LEGS + 1)]
    return tuple(names)


def feature_noise(names: Sequence[str]) -> np.ndarray:
    """Return the noise scale of each named feature (:data:`FEATURE_NOISE`'s groups)."""
    return np.array([FEATURE_NOISE[n.rsplit('_', 1)[0] if n[-1].isdigit() else n] for n in names])


def signature(record: TrialRecord, contacts: bool, settle: float = SETTLE_S) -> np.ndarray:
    """
    Return the features of ``record`` (:func:`feature_names` order) after ``settle`` s.

    ``contacts``: with the duty factors (the record must hold contacts).
    """
    keep = record.t >= record.t[0] + settle if record.t[-1] - record.t[0] > 2 * settle else None
    t = record.t if keep is None else record.t[keep]
    xy = (record.position if keep is None else record.position[keep])[:, :2]
    rpy = record.attitude if keep is None else record.attitude[keep]
    span = t[-1] - t[0]
    heading = rpy[0, 2] + record.crab
    step = xy[-1] - xy[0]
    along = (step[0] * math.cos(heading) + step[1] * math.sin(heading)) / span
    across = (-step[0] * math.sin(heading) + step[1] * math.cos(heading)) / span
    yaw = np.unwrap(rpy[:, 2])
    roll, pitch = rpy[:, 0], rpy[:, 1]
    phase = np.floor((t % record.period) / record.period * PHASE_BINS).astype(int)
    phase = np.clip(phase, 0, PHASE_BINS - 1)
    profile = []
    for series in (roll, pitch):
        centred = series - series.mean()
        profile += [
            float(centred[phase == b].mean()) if np.any(phase == b) else 0.0
            for b in range(PHASE_BINS)
        ]
    values = [along, across, (yaw[-1] - yaw[0]) / span, roll.mean(), pitch.mean(), *profile]
    if contacts:
        if record.contacts is None:
            raise ValueError('this record holds no foot contacts')
        held = record.contacts if keep is None else record.contacts[keep]
        values += list(held.mean(axis=0))
    return np.asarray(values, dtype=float)


@dataclass(frozen=True)
class GapCalibration:
    """
    How one robot's trials lie from the map's engine's walks, measured on the intact robot.

    A few gaits walked by the intact robot and by the map's engine (:func:`calibrate_gap`): the
    mean of their signatures' differences is a bias the robot adds to every walk (an IMU mounted
    a degree off, a floor that slows every gait), so ``offset`` is added to every simulated
    signature; the differences' spread around that mean is a mismatch the simulation makes gait
    by gait, so ``noise`` (each feature's scale, :func:`feature_names` order) widens
    :data:`FEATURE_NOISE` by it. ``contacts``: the features include foot duty factors.
    """

    offset: np.ndarray
    noise: np.ndarray
    contacts: bool = False

    def __post_init__(self) -> None:
        n = len(feature_names(self.contacts))
        offset = np.asarray(self.offset, dtype=float)
        noise = np.asarray(self.noise, dtype=float)
        if offset.shape != (n,) or noise.shape != (n,):
            raise ValueError(
                f'offset and noise need {n} features each, got {offset.shape} and {noise.shape}'
            )
        if not (np.isfinite(offset).all() and np.isfinite(noise).all() and np.all(noise > 0)):
            raise ValueError('a calibration needs finite offsets and noise scales > 0')
        object.__setattr__(self, 'offset', offset)
        object.__setattr__(self, 'noise', noise)


def calibrate_gap(
    observed: Sequence[TrialRecord], simulated: Sequence[TrialRecord], contacts: bool = False
) -> GapCalibration:
    """
    Return the gap between the robot's intact walks and the same gaits on the map's engine.

    ``observed[i]`` and ``simulated[i]`` are one gait, walked by the intact robot and simulated
    intact; two gaits or more (the spread needs two).
    """
    if len(observed) != len(simulated) or len(observed) < 2:
        raise ValueError(
            f'a calibration needs two or more gaits walked both ways, got {len(observed)}'
            f' and {len(simulated)}'
        )
    gap = np.array(
        [signature(o, contacts) - signature(s, contacts) for o, s in zip(observed, simulated)]
    )
    spread = gap.std(axis=0, ddof=1)
    base = feature_noise(feature_names(contacts))
    return GapCalibration(gap.mean(axis=0), np.hypot(base, spread), contacts)


def student_log_likelihood(residual: np.ndarray, nu: float = STUDENT_NU) -> float:
    """Return the log density (up to a constant) of scaled residuals under a Student-t."""
    return float(-0.5 * (nu + 1.0) * np.sum(np.log1p(np.square(residual) / nu)))


@dataclass(frozen=True)
class Posterior:
    """Each hypothesis's probability (``labels`` in order, ``NONE_LABEL`` last)."""

    labels: tuple[str, ...]
    probabilities: np.ndarray

    @property
    def leader(self) -> int:
        """Return the index of the most probable hypothesis (the last: none of these)."""
        return int(np.argmax(self.probabilities))

    def top(self, k: int = 3) -> list[tuple[str, float]]:
        """Return the ``k`` most probable hypotheses with their probabilities."""
        order = np.argsort(-self.probabilities, kind='stable')[:k]
        return [(self.labels[i], float(self.probabilities[i])) for i in order]

    def describe(self, k: int = 3) -> str:
        """Say the top hypotheses, e.g. ``legs 1, 4 lifted 0.91; none of these 0.05``."""
        return '; '.join(f'{label} {p:.2f}' for label, p in self.top(k))


#: Simulate gait ``niche`` under hypothesis ``h`` (an index into the hypotheses); None: it
#: cannot be walked.
Simulate = Callable[[int, int], 'TrialRecord | None']
#: Walk gait ``niche`` under each of the hypotheses ``hs`` ahead of :data:`Simulate` asking for
#: them one at a time (in several processes: :meth:`HypothesisWalks.prefetch`).
Prefetch = Callable[[int, Sequence[int]], None]


@dataclass
class Diagnosis:
    """
    The posterior over ``labels`` (the hypotheses) and "none of these", trial by trial.

    ``simulate(niche, h)`` walks a gait under hypothesis h on the map's engine; each walk is
    simulated when first needed and kept, and a hypothesis :data:`ASLEEP_NATS` below the most
    probable is not walked until it could matter again (a bank of every kind then walks a
    trial's gait under the few hypotheses still in play, not all); a trial wakes at most
    ``weighing.wake_walks`` walks' worth. ``contacts``: compare foot duty factors too (only when
    every trial records contacts, as a simulator's do). ``weighing``: how a trial weighs them.
    ``calibration``: the trials' source's gap to the map's engine (None: none measured).
    ``prefetch``: walks the hypotheses a trial's gait is weighed under at once (None: one by one).
    """

    labels: tuple[str, ...]
    simulate: Simulate
    contacts: bool = False
    weighing: Weighing = Weighing()
    calibration: GapCalibration | None = None
    prefetch: Prefetch | None = None
    _log: np.ndarray = field(init=False)
    _cache: dict[tuple[int, int], np.ndarray | None] = field(init=False, default_factory=dict)
    # each asleep hypothesis's trials not yet weighed: (niche, the trial's signature)
    _missed: dict[int, list[tuple[int, np.ndarray]]] = field(init=False, default_factory=dict)
    _fit: np.ndarray = field(init=False)  # each hypothesis's log likelihoods of weighed trials

    def __post_init__(self) -> None:
        if not self.labels:
            raise ValueError('a diagnosis needs at least one hypothesis')
        h, none_prior = len(self.labels), self.weighing.none_prior
        prior = np.full(h + 1, (1.0 - none_prior) / h)
        prior[-1] = none_prior
        self._log = np.log(prior)
        self._fit = np.zeros(h + 1)
        self.names = feature_names(self.contacts)
        self.noise = feature_noise(self.names)
        self.offset = np.zeros(len(self.names))
        if self.calibration is not None:
            if self.calibration.contacts != self.contacts:
                raise ValueError('the calibration and the diagnosis disagree on foot contacts')
            self.noise, self.offset = self.calibration.noise, self.calibration.offset
        self.trials = 0
        self.simulated = 0  # walks this diagnosis asked for (its own cache's misses)

    def expected(self, niche: int, h: int) -> np.ndarray | None:
        """Return gait ``niche``'s signature simulated under hypothesis ``h`` (cached)."""
        key = (int(niche), int(h))
        if key not in self._cache:
            self.simulated += 1
            record = self.simulate(*key)
            self._cache[key] = None if record is None else signature(record, self.contacts)
        return self._cache[key]

    def observe(self, niche: int, record: TrialRecord) -> Posterior:
        """Weigh the hypotheses by the trial of gait ``niche``; return the new posterior."""
        seen = signature(record, self.contacts)
        awake = self._log >= self._top() - ASLEEP_NATS
        update = np.zeros(len(self.labels) + 1)
        update[-1] = self._weight(niche, None, seen)
        weighed = [h for h in range(len(self.labels)) if awake[h] and h not in self._missed]
        if self.prefetch is not None:  # (it skips what is walked already)
            self.prefetch(niche, weighed)
        chosen = set(weighed)
        for h in range(len(self.labels)):
            if h in chosen:
                update[h] = self._weight(niche, h, seen)
            else:  # its bound stays: a likelihood is at most 1
                self._missed.setdefault(h, []).append((int(niche), seen))
        self._fit += update  # 0 where a trial was missed
        self._log = self._log + self.weighing.temperature * update
        self.trials += 1
        self._wake()
        self._log -= self._top()
        return self.posterior()

    def separation(self, niche: int) -> float:
        """
        Return how well one trial of gait ``niche`` would tell the hypotheses apart (0 to 1).

        The posterior the truth would get, were the trial exactly the truth's own walk, averaged
        over the hypotheses by their probability now ("none of these" left out; a hypothesis the
        gait cannot be walked under counts 0). Walks the gait under every hypothesis.
        """
        p = self.posterior().probabilities
        hs = [h for h in range(len(self.labels)) if p[h] > 0]
        if self.prefetch is not None:
            self.prefetch(niche, hs)
        sigs = [self.expected(niche, h) for h in hs]
        unfit = student_log_likelihood(np.full(len(self.names), self.weighing.none_deviation))
        with np.errstate(divide='ignore'):  # "none of these" may have no weight
            log_p = np.log(p[hs])
            log_none = np.log(p[-1]) + self.weighing.temperature * unfit
        score, noise = 0.0, self.noise
        for i, own in enumerate(sigs):
            if own is None:
                continue
            ll = np.array(
                [unfit if o is None else student_log_likelihood((own - o) / noise) for o in sigs]
            )
            logs = np.append(log_p + self.weighing.temperature * ll, log_none)
            score += p[hs[i]] * float(np.exp(logs[i] - logsumexp(logs)))
        return score / float(np.sum(p[hs])) if hs else 0.0

    def fits(self, h: int) -> bool:
        """Whether hypothesis ``h``'s mean log likelihood is at least the fit floor."""
        floor = self.weighing.fit_floor
        weighed = self.trials - len(self._missed.get(h, ()))
        return floor is None or weighed == 0 or bool(self._fit[h] / weighed >= floor)

    @property
    def asleep(self) -> int:
        """Return how many hypotheses the next trial will not walk (too far behind)."""
        behind = self._log[:-1] < self._top() - ASLEEP_NATS
        behind[list(self._missed)] = True
        return int(np.sum(behind))

    def _weight(self, niche: int, h: int | None, seen: np.ndarray) -> float:
        """Return the log likelihood of a trial's signature under ``h`` (None: none of these)."""
        expected = None if h is None else self.expected(niche, h)
        if expected is None:  # a gait the hypothesis cannot walk says nothing of it
            return student_log_likelihood(np.full(len(seen), self.weighing.none_deviation))
        return student_log_likelihood((seen - expected - self.offset) / self.noise)

    def _top(self) -> float:
        """Return the highest exact log posterior (none of these is always exact)."""
        exact = np.ones(len(self._log), dtype=bool)
        exact[list(self._missed)] = False
        return float(self._log[exact].max())

    def _shown(self) -> np.ndarray:
        """Return the log posterior, a bound the cap left unweighed counted as asleep."""
        shown = self._log.copy()
        if self._missed:
            missed = list(self._missed)
            shown[missed] = np.minimum(shown[missed], self._top() - ASLEEP_NATS)
        return shown

    def _wake(self) -> None:
        """
        Weigh missed trials of asleep hypotheses whose bound could matter now.

        The highest bound first, a missed trial at a time (oldest first), until it falls
        :data:`ASLEEP_NATS` behind again or has none left; within ``weighing.wake_walks``
        simulated walks (a trial already simulated costs none).
        """
        limit, start = self.weighing.wake_walks, self.simulated
        while self._missed:
            top = self._top()
            late = [h for h in self._missed if self._log[h] >= top - ASLEEP_NATS]
            if not late:
                return
            h = max(late, key=lambda k: (self._log[k], -k))
            niche, seen = self._missed[h][0]
            spent = limit is not None and self.simulated - start >= limit
            if spent and (niche, h) not in self._cache:
                return  # the rest wait for a later trial's waking
            self._missed[h].pop(0)
            if not self._missed[h]:
                del self._missed[h]
            weight = self._weight(niche, h, seen)
            self._log[h] += self.weighing.temperature * weight
            self._fit[h] += weight

    def posterior(self) -> Posterior:
        """Return the current posterior."""
        shown = self._shown()
        p = np.exp(shown - shown.max())
        return Posterior((*self.labels, NONE_LABEL), p / p.sum())


class WalksStopped(Exception):
    """A walk was not made: the ``stop()`` of :meth:`HypothesisWalks.stoppable` held."""


class HypothesisWalks:
    """
    The map's gaits walked under damages, as trials (kept: runs that share it walk each once).

    On ``engine`` (default: the map's own, at the map's physics step), for the map's trial
    duration, with the foot contacts. Within :meth:`stoppable`, a walk not made yet is made only
    while ``stop()`` is false (each takes about 0.1 s on MuJoCo, more on PyBullet). ``workers``:
    the processes :meth:`prefetch` walks a batch in (1: this one; the same walks either way).
    """

    def __init__(self, archive: Archive, engine: str | None = None, workers: int = 1) -> None:
        if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
            raise ValueError(f'workers must be a positive integer, got {workers!r}')
        self.archive = archive
        self.engine = engine or engine_of_map(archive)
        self.substeps = trial_substeps(archive, self.engine)
        self.workers = workers
        self._walks: dict[tuple[int, Damage], TrialRecord | None] = {}
        self._stop: Callable[[], bool] | None = None

    @contextmanager
    def stoppable(self, stop: Callable[[], bool] | None) -> Iterator[None]:
        """Within it, raise :class:`WalksStopped` instead of a new walk once ``stop()`` holds."""
        before, self._stop = self._stop, stop
        try:
            yield
        finally:
            self._stop = before

    def __call__(self, niche: int, damage: Damage) -> TrialRecord | None:
        """Return gait ``niche`` walked under ``damage`` (None: it cannot be walked)."""
        key = (int(niche), damage)
        if key not in self._walks:
            if self._stop is not None and self._stop():
                raise WalksStopped(f'gait {key[0]} under {damage.label} was not walked: stopped')
            self._walks[key] = _walk(self._job(key))
        return self._walks[key]

    def prefetch(self, pairs: Iterable[tuple[int, Damage]]) -> None:
        """
        Walk the (niche, damage) ``pairs`` not walked yet, in :attr:`workers` processes at once.

        What :meth:`__call__` would walk one at a time, sooner; with one worker, or one walk
        missing, it leaves them to it. A stop (:meth:`stoppable`) keeps the walks made before it.
        """
        keys = dict.fromkeys((int(niche), damage) for niche, damage in pairs)
        missing = [key for key in keys if key not in self._walks]
        if self.workers <= 1 or len(missing) < 2:
            return
        jobs = [self._job(key) for key in missing]
        worker_simulator(self.engine, self.substeps)  # made here once: forked workers inherit it
        walked = map_in_workers(_walk, jobs, min(self.workers, len(jobs)), self._stop)
        try:
            # the walks first: zip then runs them to their end, and the pool shuts down cleanly
            for record, key in zip(walked, missing):
                self._walks[key] = record
        except Stopped:
            raise WalksStopped(f'{len(missing)} walks were not all made: stopped') from None

    def _job(self, key: tuple[int, Damage]) -> _WalkJob:
        """Return what a process needs to walk gait ``key[0]`` under ``key[1]``."""
        genes = self.archive.genotypes[key[0]]
        return (self.engine, self.substeps, genes, key[1], self.archive.trial_duration)

    @property
    def walked(self) -> int:
        """Return how many walks were simulated."""
        return len(self._walks)

    def under(self, damages: Sequence[Damage]) -> Simulate:
        """Return ``simulate(niche, h)`` over ``damages`` for a :class:`Diagnosis`."""
        return lambda niche, h: self(niche, damages[h])

    def prefetcher(self, damages: Sequence[Damage]) -> Prefetch:
        """Return ``prefetch(niche, hs)`` over ``damages`` for a :class:`Diagnosis`."""
        return lambda niche, hs: self.prefetch((niche, damages[h]) for h in hs)


#: (engine, physics substeps, genes, damage, trial duration [s]): one walk, picklable.
_WalkJob = tuple[str, int, np.ndarray, Damage, float]


def _walk(job: _WalkJob) -> TrialRecord | None:
    """Walk one gait under one damage in this process's simulator (None: it cannot be walked)."""
    engine, substeps, genes, damage, duration = job
    trace = trace_gait(genes, worker_simulator(engine, substeps), damage, duration)
    return None if trace is None else TrialRecord.from_trace(trace)
