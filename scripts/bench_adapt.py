# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
The adaptation benchmarks (``make bench-adapt``; scripts/bench.py runs them).

Every figure on its own line as ``BENCH <name> <value> <unit>`` (docs/benchmarks.md).
"""

from __future__ import annotations

from dataclasses import replace
import sys
import time
from typing import Sequence

import numpy as np


def bench_adapt() -> None:
    """
    Adaptation benchmarks.

    adapt_mboa_step_ms: one M-BOA step (observe a trial + pick the next gait) on a 40 000-gait map
    after 19 trials (median of 20 runs' last steps). adapt_prior_rescore_s: the default map
    re-scored under a damage no cache holds (leg 3 locked), 2 processes; adapt_rescore_named_s:
    the top of it re-scored under the same damage as a blind run does on naming it (one
    process). Then thesis experiment 5.2
    on the default map (``BENCH_ADAPT_MAP`` overrides it): every orientation of S1-S4, with trials
    on the map's engine and again across engines (suffix _cross), in three setups: the default
    profile (no suffix; the damaged control tripod is each run's success floor; blind, each run
    names its damage among adapt_node's default bank (:data:`DEFAULT_DIAGNOSIS_BANK`: the 21
    lifted-leg hypotheses, every kind's 168 once none of those fits) as its blind requests do:
    adapt_diagnosis_correct, the runs whose damage was named after 2 trials, and
    adapt_best_after_<k>, the mean best after k trials), the default
    profile starting from the damage-informed prior (suffix _prior), and the thesis profile (suffix
    _thesis; the thesis rule, no floor). Per run: the best speed found, the trials, the control
    tripod with the same damage, and the ratio to the map's ceiling under the damage (cached
    ceilings only; across engines, approximate PyBullet ceilings if cached -- none are shipped:
    studies/adaptation/README.md says why). Runs end by M-BOA's
    stopping rule, capped at the budget users get (24 trials), and for the thesis profile at
    EXPERIMENT_MAX_TRIALS (100) so that its rule ends them. Trials are 5 s from standing (the
    product's and the thesis's trial), with adapt_node's tip guard (a trial that tilts the body
    past 30 deg scores 0; adapt_tipped_trials counts them). Then the default profile, blind
    (_judge) and from the damage-informed prior (_prior_judge), with trials on the judge engine
    (DART). Trials on an engine that did not make the map (_cross, _judge), and its ceilings, run
    at its converged step (``map_physics``, ``SimConfig.converged``). Last, the experiment on
    every damage kind (:func:`_bench_damage_kinds`); ``BENCH_ADAPT_KINDS`` (kinds separated by
    spaces) runs that alone, for those kinds. ``BENCH_ADAPT_SETUPS`` (some of ``default prior
    thesis``) runs only those setups of S1-S4, on every engine, without the timings or the kinds:
    to measure again the figures one change can move.
    """
    import os
    from pathlib import Path

    from hexapod_adapt.mapping.archive import load_archive
    from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_ceilings, shipped_map
    from hexapod_adapt.mapping.simulation import engine_of_map
    from hexapod_adapt.online.adaptation import DEFAULT_TIP_GUARD
    from hexapod_adapt.online.bank import load_diagnosis_banks
    from hexapod_adapt.online.ceiling import (
        approximate_ceiling,
        approximate_key,
        cached_ceiling,
        ceiling,
        ceiling_key,
        holds_ceiling,
    )
    from hexapod_adapt.online.experiment import ExperimentSetup, run_experiment
    from hexapod_adapt.online.mboa import PROFILES, TRIAL_BUDGET
    from hexapod_sim import ENGINES
    from hexapod_sim.scenarios import scenario
    from hexapod_sim.simulator import JUDGE_ENGINE

    path = Path(os.environ.get('BENCH_ADAPT_MAP', shipped_map(DEFAULT_MAP)))
    print(f'# experiment on {path}', file=sys.stderr)
    archive = load_archive(path)
    map_engine = engine_of_map(archive)
    cached = shipped_ceilings()
    legs_all = [legs for name in ('S1', 'S2', 'S3', 'S4') for legs in scenario(name)]
    only_kinds = os.environ.get('BENCH_ADAPT_KINDS', '').split()
    if only_kinds:
        _bench_damage_kinds(archive, map_engine, cached, legs_all, only_kinds)
        return
    only_setups = set(os.environ.get('BENCH_ADAPT_SETUPS', '').split())
    if only_setups - set(SETUPS):
        raise SystemExit(
            f'unknown setups {sorted(only_setups - set(SETUPS))} in BENCH_ADAPT_SETUPS:'
            f' each is one of {list(SETUPS)}'
        )
    chosen = only_setups or set(SETUPS)
    if not only_setups:
        _bench_timings(archive, map_engine)
    other = next(e for e in ENGINES if e != map_engine)

    def ceilings(legs, engine):
        if engine == map_engine:
            return ceiling(archive, legs, engine, cached)
        guide = ceiling(archive, legs, map_engine, cached)
        return approximate_ceiling(archive, legs, engine, guide, CROSS_TOP, cached)

    def key(legs, engine):
        if engine == map_engine:
            return ceiling_key(archive, legs, engine)
        return approximate_key(archive, legs, engine, map_engine, CROSS_TOP)

    def priors(legs):  # the map re-scored under the damage on its own engine (cached)
        return ceiling(archive, legs, map_engine, cached).speeds

    # read, not only found: a damaged or stale file counts as missing (its figures are skipped)
    have_priors = all(
        cached_ceiling(archive, legs, map_engine, [cached]) is not None for legs in legs_all
    )
    if have_priors:  # what the map holds under each scenario's damage (the shipped cache)
        for name in ('S1', 'S2', 'S3', 'S4'):
            best = [
                ceiling(archive, legs, map_engine, cached).best_speed for legs in scenario(name)
            ]
            print(f'BENCH map_ceiling_median_{name} {np.median(best):.3f} m/s')
    # (suffix, profile, floor, informed) for the setups chosen
    setups = [
        (label, name, floor, informed)
        for setup, (label, name, floor, informed) in SETUPS.items()
        if setup in chosen and (have_priors or not informed)
    ]
    # blind default runs name their damage among the shipped bank, as adapt_node's blind runs do
    bank, wider = load_diagnosis_banks(archive, map_engine, [cached])
    for engine, cross in ((map_engine, ''), (other, '_cross')):
        # cached ceilings only (loose or packed): a missing PyBullet ceiling costs many minutes
        have = all(holds_ceiling(cached, key(legs, engine)) for legs in legs_all)
        for label, name, floor, informed in setups:
            suffix = label + cross
            config = PROFILES[name]
            rows = run_experiment(
                archive,
                ExperimentSetup(
                    config=replace(config, max_trials=100 if name == 'thesis' else TRIAL_BUDGET),
                    # another engine's trials and ceilings at its converged step (map_physics)
                    trial_engine=engine,
                    ceilings=ceilings if have else None,
                    floor=floor,
                    priors=priors if informed else None,
                    setup=name + ('+prior' if informed else ''),
                    tip_guard=DEFAULT_TIP_GUARD,
                    bank=bank if name == 'default' else None,
                    wider=wider if name == 'default' else None,
                    diagnose=name == 'default' and not informed,
                    walk_workers=2,  # adapt_node's prior_workers: the same walks, sooner
                ),
            )
            _print_experiment(rows, suffix, have, engine, cached)
    # the judge: trials walked on the engine that takes no part in making or tuning anything
    if map_engine != JUDGE_ENGINE:
        for label, name, _floor, informed in setups:
            if name == 'thesis':  # the judge walks the product's profile only
                continue
            rows = run_experiment(
                archive,
                ExperimentSetup(
                    config=replace(PROFILES['default'], max_trials=TRIAL_BUDGET),
                    trial_engine=JUDGE_ENGINE,  # at its converged step (map_physics)
                    floor=True,
                    priors=priors if informed else None,
                    setup='default' + ('+prior' if informed else ''),
                    tip_guard=DEFAULT_TIP_GUARD,
                    bank=bank,
                    wider=wider,
                    diagnose=not informed,
                    walk_workers=2,
                ),
            )
            _print_experiment(rows, f'{label}_judge', False, JUDGE_ENGINE, cached)
    if not only_setups:
        _bench_damage_kinds(archive, map_engine, cached, legs_all)


#: The experiment's setups of S1-S4, by the name BENCH_ADAPT_SETUPS takes: (BENCH suffix, M-BOA
#: profile, the damaged tripod as the success floor, from the damage-informed prior).
SETUPS = {
    'default': ('', 'default', True, False),
    'prior': ('_prior', 'default', True, True),
    'thesis': ('_thesis', 'thesis', False, False),
}


def _bench_timings(archive, map_engine: str) -> None:
    """One M-BOA step, the map's size, and the damage-informed prior's re-score and first trial."""
    import tempfile

    from hexapod_adapt.online.ceiling import quick_rescore, RescoreStopped
    from hexapod_adapt.online.mboa import Mboa, MboaConfig
    from hexapod_adapt.online.prior import damage_prior
    from hexapod_adapt.online.streaming_prior import StreamingPrior
    from hexapod_sim.damage import Damage

    rng = np.random.default_rng(0)
    descriptors, prior = rng.random((40000, 6)), rng.uniform(0.1, 0.45, 40000)
    steps = []
    for _ in range(20):
        opt = Mboa(descriptors, prior, MboaConfig(max_trials=20))
        for _ in range(19):
            opt.observe(opt.next_index(), float(rng.uniform(0, 0.3)))
        t0 = time.perf_counter()
        opt.observe(opt.next_index(), 0.2)
        steps.append(time.perf_counter() - t0)
    print(f'BENCH adapt_mboa_step_ms {np.median(steps) * 1e3:.2f} ms')
    print(f'BENCH adapt_map_gaits {archive.n_filled} gaits')
    # the damage-informed prior: the whole map re-scored under a damage no cache holds, as
    # adapt_node does before a run (2 processes, the project machine's cores)
    with tempfile.TemporaryDirectory() as scratch:
        rescored = damage_prior(archive, Damage.of('locked', [3]), map_engine, scratch, workers=2)
    print(f'BENCH adapt_prior_rescore_s {rescored.seconds:.1f} s')
    # the streaming prior: the time until the top of the map is re-scored and the first trial
    # may start (the rest streams in between trials), same damage, no cache
    with tempfile.TemporaryDirectory() as scratch:
        t0 = time.monotonic()
        stream = StreamingPrior(archive, Damage.of('locked', [3]), map_engine, scratch, workers=2)
        stream.wait_first(600)
        print(f'BENCH adapt_prior_first_trial_s {time.monotonic() - t0:.1f} s')
        stream.close()
    # a blind run naming a damage its bank has not cached: the top of the map re-scored under
    # it between two trials, in adapt_node's prior_workers processes (2, its default)
    t0 = time.monotonic()
    quick_rescore(archive, Damage.of('locked', [3]), map_engine, workers=2)
    print(f'BENCH adapt_rescore_named_s {time.monotonic() - t0:.1f} s')
    # a cancel during that re-score: how long after it the re-score stops (a run cancelled then)
    asked = time.monotonic() + 3.0
    try:
        quick_rescore(
            archive,
            Damage.of('locked', [4]),
            map_engine,
            stop=lambda: time.monotonic() >= asked,
            workers=2,
        )
    except RescoreStopped:
        print(f'BENCH adapt_rescore_cancel_s {time.monotonic() - asked:.2f} s')
    _bench_blind_first_ask(archive, map_engine)


def _bench_blind_first_ask(archive, map_engine: str) -> None:
    """A fresh node's first blind run: the time its first ask takes, and a cancel during it."""
    from hexapod_adapt.mapping.maps import shipped_ceilings
    from hexapod_adapt.online.adaptation import DEFAULT_TIP_GUARD
    from hexapod_adapt.online.bank import load_diagnosis_banks
    from hexapod_adapt.online.diagnosis import HypothesisWalks
    from hexapod_adapt.online.mboa import PROFILES
    from hexapod_adapt.online.session import AdaptationSession, diagnosis_plan, SessionStart

    bank, wider = load_diagnosis_banks(archive, map_engine, [shipped_ceilings()])

    # the walks in adapt_node's prior_workers processes (2, its default), and in one
    def first_ask(stop=None, workers=2, **kin) -> tuple[float, int, AdaptationSession]:
        walks = HypothesisWalks(archive, map_engine, workers)
        plan = diagnosis_plan(archive, bank, DEFAULT_TIP_GUARD, walks=walks, wider=wider, **kin)
        session = AdaptationSession(archive, PROFILES['default'], SessionStart(diagnosis=plan))
        t0 = time.monotonic()
        session.ask(stop)
        return time.monotonic() - t0, walks.walked, session

    for suffix, kin in (
        ('', {}),
        ('_no_kin', {'kin_tilts': None}),
        ('_one_process', {'workers': 1}),
    ):
        seconds, walked, _ = first_ask(**kin)
        print(f'BENCH adapt_blind_first_ask_s{suffix} {seconds:.1f} s')
        print(f'BENCH adapt_blind_first_ask_walks{suffix} {walked} walks')
    asked = time.monotonic() + 1.0  # a cancel 1 s into it: how long until the run has ended
    _, _, session = first_ask(lambda: time.monotonic() >= asked)
    if session.finished and session.result().message == 'cancelled':
        print(f'BENCH adapt_blind_cancel_s {time.monotonic() - asked:.2f} s')


def _bench_damage_kinds(
    archive, map_engine: str, cached, legs_all, kinds: Sequence[str] = ()
) -> None:
    """
    Adaptation on every damage kind (issue 31): the default profile, blind and with the prior.

    Per kind K: adapt_beats_control_<K> (of the 21 S1-S4 cases), adapt_speed_mean_<K>,
    adapt_tipped_trials_<K> and, where the shipped cache holds the kind's 21 ceilings,
    adapt_ceiling_ratio_median_<K> and _min_<K>; the same with the damage-informed prior (suffix
    _prior), which needs those ceilings. Blind runs name their damage among the hypotheses
    adapt_node's blind requests weigh (:data:`DEFAULT_DIAGNOSIS_BANK`):
    adapt_diagnosis_correct_<K> (kind and legs named after 3 trials), adapt_trials_median_<K>
    and adapt_best_after_<k>_<K>; blind runs are walked again on the other engine (suffix
    _cross, at its converged step). Trials have adapt_node's tip guard, as the experiment's.
    ``kinds``: these kinds only (default: every one).
    """
    from hexapod_adapt.online.adaptation import DEFAULT_TIP_GUARD
    from hexapod_adapt.online.bank import load_diagnosis_banks
    from hexapod_adapt.online.ceiling import cached_ceiling, ceiling
    from hexapod_adapt.online.experiment import ExperimentSetup, run_experiment
    from hexapod_adapt.online.mboa import PROFILES, TRIAL_BUDGET
    from hexapod_sim import ENGINES
    from hexapod_sim.damage import Damage, EXPERIMENT_KINDS

    unknown = set(kinds) - set(EXPERIMENT_KINDS)
    if unknown:
        raise SystemExit(f'unknown damage kinds {sorted(unknown)}: one of {EXPERIMENT_KINDS}')
    config = replace(PROFILES['default'], max_trials=TRIAL_BUDGET)
    bank, wider = load_diagnosis_banks(archive, map_engine, [cached])  # adapt_node's
    other = next(e for e in ENGINES if e != map_engine)
    for kind in kinds or EXPERIMENT_KINDS:
        damages = [Damage.of(kind, legs) for legs in legs_all]
        have = all(cached_ceiling(archive, d, map_engine, [cached]) is not None for d in damages)
        if not have:
            print(f'# no cached ceilings of kind {kind}: no ratios, no prior', file=sys.stderr)

        def ceilings(damage, engine):
            return ceiling(archive, damage, engine, cached)

        for suffix, informed, engine in (
            ('', False, map_engine),
            ('_prior', True, map_engine),
            ('_cross', False, other),
        ):
            if informed and not have:
                continue
            rows = run_experiment(
                archive,
                ExperimentSetup(
                    config=config,
                    trial_engine=engine,  # another engine at its converged step (map_physics)
                    ceilings=ceilings if have and engine == map_engine else None,
                    floor=True,
                    priors=(lambda d: ceilings(d, map_engine).speeds) if informed else None,
                    setup='default' + ('+prior' if informed else ''),
                    kind=kind,
                    tip_guard=DEFAULT_TIP_GUARD,
                    bank=bank,
                    wider=wider,
                    diagnose=not informed,
                    walk_workers=2,
                ),
            )
            if not informed:  # kind and legs, named by trial 3 (issue 67's target)
                _print_diagnosis(rows, f'_{kind}{suffix}', 3)
                trials = np.median([r.trials for r in rows])
                print(f'BENCH adapt_trials_median_{kind}{suffix} {trials:.1f} trials')
            best = np.array([r.best_speed for r in rows])
            control = np.array([r.control_speed for r in rows])
            name = f'{kind}{suffix}'
            beats = int(np.sum(best > control))
            print(f'BENCH adapt_beats_control_{name} {beats} of {len(rows)} runs')
            print(f'BENCH adapt_speed_mean_{name} {best.mean():.3f} m/s')
            print(f'BENCH control_speed_mean_{name} {control.mean():.3f} m/s')
            print(f'BENCH adapt_tipped_trials_{name} {sum(r.tipped_trials for r in rows)} trials')
            if have and engine == map_engine:
                ratio = np.median([r.ratio for r in rows])
                print(f'BENCH adapt_ceiling_ratio_median_{name} {ratio:.3f} 1')
                print(f'BENCH adapt_ceiling_ratio_min_{name} {min(r.ratio for r in rows):.3f} 1')


#: Across engines the ceiling is PyBullet over the gaits that walk best under the damage on MuJoCo.
CROSS_TOP = 1000


def _print_experiment(rows, suffix: str, have: bool, engine: str, cached) -> None:
    """Print one experiment's BENCH lines (``have``: its rows carry ceiling ratios)."""
    if have:
        ratios = {r.scenario: [] for r in rows}
        for r in rows:
            ratios[r.scenario].append(r.ratio)
        for name, values in ratios.items():
            print(f'BENCH adapt_ceiling_ratio_median_{name}{suffix} {np.median(values):.3f} 1')
        print(f'BENCH adapt_ceiling_ratio_min{suffix} {min(r.ratio for r in rows):.3f} 1')
    else:
        print(f'# no cached ceilings for {engine} in {cached}: no ratios', file=sys.stderr)
    print(
        f'BENCH adapt_walking_s_median{suffix} {np.median([r.walking_time for r in rows]):.1f} s'
    )
    best = np.array([r.best_speed for r in rows])
    control = np.array([r.control_speed for r in rows])
    print(f'BENCH adapt_speed_mean{suffix} {best.mean():.3f} m/s')
    for name in ('S1', 'S2', 'S3', 'S4'):
        sel = [r for r in rows if r.scenario == name]
        print(
            f'BENCH adapt_speed_median_{name}{suffix}'
            f' {np.median([r.best_speed for r in sel]):.3f} m/s'
        )
        print(
            f'BENCH adapt_trials_median_{name}{suffix}'
            f' {np.median([r.trials for r in sel]):.1f} trials'
        )
    print(f'BENCH control_speed_mean{suffix} {control.mean():.3f} m/s')
    print(f'BENCH control_speed_intact{suffix} {rows[0].intact_control_speed:.3f} m/s')
    print(f'BENCH adapt_beats_control{suffix} {int(np.sum(best > control))} of {len(rows)} runs')
    print(
        f'BENCH adapt_within_24_trials{suffix} {sum(r.trials <= 24 for r in rows)} of'
        f' {len(rows)} runs'
    )
    print(f'BENCH adapt_trials_max{suffix} {max(r.trials for r in rows)} trials')
    print(f'BENCH adapt_trials_median{suffix} {np.median([r.trials for r in rows]):.1f} trials')
    print(f'BENCH adapt_tipped_trials{suffix} {sum(r.tipped_trials for r in rows)} trials')
    # the run's best met M-BOA's rule (alpha, the floor) when it ended, by the rule or at the
    # budget (a blind default run goes on for an expected gain; until 2026-11-25: ended by it)
    print(
        f'BENCH adapt_stopped_by_rule{suffix} {sum(r.success for r in rows)} of {len(rows)} runs'
    )
    if any(r.named for r in rows):  # a diagnosing run: the damage named, the anytime curve
        _print_diagnosis(rows, suffix, 2)


def _print_diagnosis(rows, suffix: str, by: int) -> None:
    """Print the runs whose damage was named after ``by`` trials, and the anytime curve."""
    from hexapod_sim.damage import Damage

    truth = [Damage.of(r.damage_kind, r.failed_legs).label for r in rows]
    correct = sum(r.named_after(by) == label for r, label in zip(rows, truth))
    print(f'BENCH adapt_diagnosis_correct{suffix} {correct} of {len(rows)} runs')
    for k in (1, 3, 5, 8, 12, 24):
        best = np.mean([r.best_after(k) for r in rows])
        print(f'BENCH adapt_best_after_{k}{suffix} {best:.3f} m/s')
