#!/usr/bin/env python3
# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Benchmarks. Each figure is printed on its own line as ``BENCH <name> <value> <unit>``.

python scripts/bench.py all|gait|sim|map|adapt|bridge|navigate|firmware
"""

from __future__ import annotations

from dataclasses import replace
import sys
import time

import numpy as np


def bench_gait() -> None:
    """
    Gait benchmarks.

    gait_build_ms: genotype -> 240 Hz joint table (what MAP-Elites does per evaluation),
    median over feasible random genotypes after warm-up.
    """
    from hexapod_gait import build_joint_table, from_genotype, ReachabilityError

    rng = np.random.default_rng(1)
    feasible = []
    while len(feasible) < 200:
        g = rng.random(32)
        try:
            build_joint_table(from_genotype(g))
            feasible.append(g)
        except ReachabilityError:
            pass
    samples = []
    for _ in range(5):
        for g in feasible:
            t0 = time.perf_counter()
            build_joint_table(from_genotype(g))
            samples.append(time.perf_counter() - t0)
    print(f'BENCH gait_build_ms {np.median(samples) * 1e3:.3f} ms')
    print(f'BENCH gait_build_p95_ms {np.percentile(samples, 95) * 1e3:.3f} ms')


def bench_sim() -> None:
    """
    Both engines in one run, on one pinned core, interleaved gait by gait.

    sim_eval_ms (PyBullet) and sim_eval_mujoco_ms: median time of one whole 5 s evaluation (reset,
    contacts and collision checks included; one gait per call) over seeded random feasible gaits;
    sim_eval_mujoco_batch8_ms: the same gaits in MuJoCo batches of 8 (what a map-generation worker
    does); sim_engine_speedup: PyBullet ms / MuJoCo ms. sim_engine_spearman: rank correlation of
    the two engines' fitness over the shipped demo map's gaits (walking gaits of all speeds),
    collisions not fatal; sim_engine_descriptor_mad: their mean absolute duty-factor difference.
    sim_engine_tripod_ratio: intact control tripod speed, MuJoCo / PyBullet. sim_eval_dart_ms and
    sim_tripod_speed_dart: the same for DART, the judge engine (interleaved with the other two).
    """
    import os
    from pathlib import Path

    from hexapod_gait import preset
    from hexapod_sim import create_simulator, evaluate_gait, evaluate_gaits, SimConfig
    from hexapod_sim.fidelity import agreement
    from hexapod_sim.fidelity_table_cli import map_genotypes
    from hexapod_sim.sampling import random_feasible_genotypes

    if hasattr(os, 'sched_setaffinity'):
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    n = int(os.environ.get('BENCH_SIM_GAITS', '100'))
    bullet = create_simulator(SimConfig(engine='pybullet'))
    mujoco = create_simulator(SimConfig(engine='mujoco'))
    dart = create_simulator(SimConfig(engine='dart'))
    genotypes, _ = random_feasible_genotypes(n, seed=2024, sim=bullet)

    def timed(sim, genes) -> float:
        t0 = time.perf_counter()
        evaluate_gait(genes, sim, collisions_fatal=True)
        return time.perf_counter() - t0

    evaluate_gait(genotypes[0], mujoco)  # warm-up
    t_bullet, t_mujoco, t_dart = [], [], []
    for genes in genotypes:  # interleaved: every engine sees the same machine state
        t_bullet.append(timed(bullet, genes))
        t_mujoco.append(timed(mujoco, genes))
        t_dart.append(timed(dart, genes))
    batch = []
    for i in range(0, n - 7, 8):
        t0 = time.perf_counter()
        evaluate_gaits(list(genotypes[slice(i, i + 8)]), mujoco, collisions_fatal=True)
        batch.append((time.perf_counter() - t0) / 8)
    ms_bullet, ms_mujoco = np.median(t_bullet) * 1e3, np.median(t_mujoco) * 1e3
    print(f'BENCH sim_feasible_gaits {n} gaits')
    print(f'BENCH sim_eval_ms {ms_bullet:.1f} ms')
    print(f'BENCH sim_eval_mujoco_ms {ms_mujoco:.1f} ms')
    print(f'BENCH sim_eval_mujoco_batch8_ms {np.median(batch) * 1e3:.1f} ms')
    print(f'BENCH sim_engine_speedup {ms_bullet / ms_mujoco:.2f} x')
    print(f'BENCH sim_eval_dart_ms {np.median(t_dart) * 1e3:.1f} ms')
    demo = Path(__file__).resolve().parent.parent / 'hexapod_adapt' / 'maps' / 'demo_map.npz'
    a = agreement(map_genotypes(demo), bullet, mujoco)
    print(f'BENCH sim_engine_agreement_gaits {a.gaits} gaits')
    print(f'BENCH sim_engine_spearman {a.spearman:.4f} 1')
    print(f'BENCH sim_engine_descriptor_mad {a.mean_abs_descriptor:.4f} 1')
    tripod = [
        evaluate_gait(preset('control'), sim, collisions_fatal=False, failed_legs=()).speed
        for sim in (bullet, mujoco, dart)
    ]
    print(f'BENCH sim_tripod_speed_pybullet {tripod[0]:.4f} m/s')
    print(f'BENCH sim_tripod_speed_mujoco {tripod[1]:.4f} m/s')
    print(f'BENCH sim_tripod_speed_dart {tripod[2]:.4f} m/s')
    print(f'BENCH sim_engine_tripod_ratio {tripod[1] / tripod[0]:.4f} 1')


def bench_bridge() -> None:
    """
    bridge_parse_frames_per_s.

    Robot->PC frames (extension reports) the host parser decodes per second; bridge_upload_ms: one
    gait upload (35 SET_PARAM + COMMIT, acknowledged) over an emulated clean 19200-baud link,
    emulated time; bridge_link_down_max_ms / bridge_link_up_max_ms: the slowest of 10 radio-port
    losses to be reported, and of 10 returns to bring telemetry back, through the ROS graph.
    """
    from hexapod_bridge import extension as ext
    from hexapod_bridge.emulator.firmware import RobotFirmware
    from hexapod_bridge.link import RobotLink
    from hexapod_bridge.stream import HostParser
    from hexapod_gait import preset

    stream = b''.join(
        ext.encode_report(ext.Report.TRIAL, i, bytes([1, 0, 0, i & 0xFF])) for i in range(50_000)
    )
    parser = HostParser()
    t0 = time.perf_counter()
    for k in range(0, len(stream), 4096):
        parser.feed(stream[slice(k, k + 4096)])
    rate = parser.stats.frames_ok / (time.perf_counter() - t0)
    print(f'BENCH bridge_parse_frames_per_s {rate:.0f} frames/s')
    durations = []
    for archive_index in range(20):
        link, fw = RobotLink(), RobotFirmware()
        link.arm(True, 0.0)
        op, t, wire_free = (
            link.upload(preset('tripod').replace(archive_index=archive_index)),
            0.0,
            0.0,
        )
        while not op.done and t < 10.0:
            t += 0.0005
            for frame in link.poll(t):
                wire_free = max(wire_free, t) + len(frame) / 1920.0
                fw.receive(frame, wire_free)
            radio, _ = fw.advance(t)
            link.receive(radio, t + len(radio) / 1920.0)
        assert op.ok, op.message
        durations.append(t)
    print(f'BENCH bridge_upload_ms {np.median(durations) * 1e3:.0f} ms')
    down, up = _port_loss_latencies()
    print(f'BENCH bridge_link_down_max_ms {max(down) * 1e3:.0f} ms')
    print(f'BENCH bridge_link_up_max_ms {max(up) * 1e3:.0f} ms')


def _port_loss_latencies(cycles: int = 10) -> tuple[list[float], list[float]]:
    """
    Time radio-port losses and returns through the ROS graph (seconds, one per cycle).

    Down: from the port vanishing to a "not connected" LinkStatus; up: from its return to the
    next IMU message; ``cycles`` losses of 1 s. robot_emulator and bridge_node run as processes
    on a private DDS domain; the port's changes are timed by the emulator's own CLOCK_MONOTONIC
    stamps, not by the signals that cause them.
    """
    import os
    from pathlib import Path
    import signal
    import subprocess
    import tempfile

    from hexapod_bridge.bridge_node import reports_down_since
    from hexapod_bridge.emulator.robot_emulator_cli import radio_gone_times
    from hexapod_msgs.msg import LinkStatus
    from hexapod_util.ros_glue import ros_args
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import qos_profile_sensor_data
    from sensor_msgs.msg import Imu

    domain = 91 + os.getpid() % 10  # the tests use 1-40, make demo 60-89
    env = dict(os.environ, ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST')
    down: list[float] = []
    up: list[float] = []
    with tempfile.TemporaryDirectory() as tmp:
        radio, log = f'{tmp}/radio', Path(tmp) / 'emulator.log'
        procs = []
        context = rclpy.Context()
        rclpy.init(context=context, domain_id=domain)
        try:
            with log.open('w') as out:
                procs.append(
                    subprocess.Popen(
                        ['robot_emulator', '--radio-link', radio, '--imu-link', f'{tmp}/imu'],
                        stdout=out,
                        stderr=subprocess.STDOUT,
                        env=env,
                    )
                )
            node = rclpy.create_node('bench_port_loss', context=context)
            executor = SingleThreadedExecutor(context=context)
            executor.add_node(node)
            links: list = []
            imu_times: list[float] = []
            node.create_subscription(LinkStatus, 'bridge_node/link_status', links.append, 10)
            node.create_subscription(
                Imu,
                'imu/data',
                lambda _: imu_times.append(time.monotonic()),
                qos_profile_sensor_data,
            )

            def spin_until(predicate, timeout: float, what: str) -> None:
                deadline = time.monotonic() + timeout
                while not predicate():
                    if time.monotonic() > deadline:
                        raise RuntimeError(f'port-loss benchmark: no {what} within {timeout:g} s')
                    executor.spin_once(timeout_sec=0.005)

            spin_until(lambda: os.path.exists(radio), 60, 'emulated radio port')
            procs.append(
                subprocess.Popen(
                    ['bridge_node']
                    + ros_args({'port': radio, 'arm_on_start': True, 'telemetry_period': 0.2}),
                    stdout=subprocess.DEVNULL,
                    stderr=subprocess.DEVNULL,
                    env=env,
                )
            )
            spin_until(lambda: imu_times, 60, 'first telemetry')
            for cycle in range(cycles):
                wall = time.time()
                procs[0].send_signal(signal.SIGUSR1)
                spin_until(lambda: len(radio_gone_times(log.read_text())) > cycle, 10, 'loss')
                t_gone = radio_gone_times(log.read_text())[cycle]
                spin_until(
                    lambda: links and reports_down_since(links[-1], wall), 5, 'link-down report'
                )
                down.append(time.monotonic() - t_gone)
                spin_until(lambda: time.monotonic() > t_gone + 1.0, 2, 'pause')
                procs[0].send_signal(signal.SIGUSR2)
                spin_until(lambda: log.read_text().count('RADIO /') > cycle + 1, 10, 'return')
                t_back = time.monotonic()
                spin_until(lambda: imu_times[-1] > t_back, 5, 'telemetry after the return')
                up.append(time.monotonic() - t_back)
        finally:
            for proc in reversed(procs):
                proc.send_signal(signal.SIGINT)
                try:
                    proc.wait(10)
                except subprocess.TimeoutExpired:
                    proc.kill()
                    proc.wait()
            rclpy.try_shutdown(context=context)
    return down, up


def _default_map_figures() -> None:
    """
    The shipped default map's own figures, from its metadata and its generation log.

    map_core_hours: the wall time of each run in the log (a resumed run restarts ``elapsed``)
    times its workers (a row's ``workers``; logs written before rows had it: the 2 workers its
    README records): the cores the runs held. map_cpu_core_hours: the CPU time the runs used
    (their rows' ``cpu_s``), printed when every row has it; less than map_core_hours when the
    machine was busy with other work too.
    """
    from hexapod_adapt.mapping.archive import load_archive
    from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
    from hexapod_adapt.mapping.plots import log_runs

    path = shipped_map(DEFAULT_MAP)
    archive = load_archive(path)
    speeds = archive.speeds()[archive.elite_indices()]
    runs = log_runs(path.with_name(path.name + '.log.jsonl'))
    print(f'BENCH map_evaluations {archive.metadata["evaluations"]} evaluations')
    print(f'BENCH map_core_hours {sum(r.core_seconds for r in runs) / 3600:.2f} core-hours')
    if runs and all(r.cpu_s is not None for r in runs):
        print(f'BENCH map_cpu_core_hours {sum(r.cpu_s for r in runs) / 3600:.2f} core-hours')
    print(f'BENCH map_filled {archive.n_filled} niches')
    print(f'BENCH map_mean_elite {speeds.mean():.3f} m/s')
    print(f'BENCH map_best {speeds.max():.3f} m/s')


def _transfer_figures() -> None:
    """
    The default map's gaits on the engines that did not make it (intact, 5 s from standing).

    map_<engine>_top100_speed_median and map_<engine>_top100_tipped (past 60 deg of roll or
    pitch) over its 100 fastest gaits; map_<engine>_spearman: the map's speeds against the
    engine's over its 300 fastest and 100 others at random (seed 0). Engines: the judge (DART,
    as map_judge_...) and PyBullet (map_pybullet_...), or any other that did not make the map.
    """
    from hexapod_adapt.mapping.archive import load_archive
    from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
    from hexapod_adapt.mapping.simulation import archive_engine
    from hexapod_adapt.mapping.transfer import transfer_figures
    from hexapod_sim import create_simulator, ENGINES, SimConfig
    from hexapod_sim.simulator import JUDGE_ENGINE

    archive = load_archive(shipped_map(DEFAULT_MAP))
    made_on = archive_engine(archive.metadata)
    for engine in (e for e in ENGINES if e != made_on):
        name = 'judge' if engine == JUDGE_ENGINE else engine
        with create_simulator(SimConfig(engine=engine)) as sim:
            f = transfer_figures(archive, sim)
        print(f'BENCH map_{name}_top100_speed_median {f.top_speed_median:.3f} m/s')
        print(f'BENCH map_{name}_top100_tipped {f.top_tipped} gaits')
        print(f'BENCH map_{name}_spearman {f.spearman:.3f} 1')


def bench_map() -> None:
    """
    The default map's own figures and those on other engines, then the generator's speed.

    map_evals_per_s_mujoco and map_worker_utilisation_mujoco.

    A generate_map run from scratch on 2 local worker processes with the MuJoCo engine (batches of
    8), 3000 evaluations into a 500-niche map: evaluations per second and worker compute time /
    (workers x wall time). map_evals_per_s (PyBullet, 2 workers, 600 evaluations) for comparison.
    map_archive_save_ms: writing a 40 000-niche archive atomically.
    """
    from pathlib import Path
    import tempfile

    from hexapod_adapt.mapping.archive import Archive
    from hexapod_adapt.mapping.generate import generate_map, GenerateConfig

    _default_map_figures()
    _transfer_figures()
    with tempfile.TemporaryDirectory() as tmp:
        for engine, evaluations, suffix in (('mujoco', 3000, '_mujoco'), ('pybullet', 600, '')):
            last = []
            cfg = GenerateConfig(
                out=Path(tmp) / engine / 'map.npz',
                niches=500,
                evaluations=evaluations,
                seed=1,
                workers=2,
                engine=engine,
                log_every=1.0,
            )
            generate_map(cfg, on_progress=last.append)
            p = last[-1]
            print(f'BENCH map_workers{suffix} {cfg.worker_count()} processes')
            print(f'BENCH map_evals_per_s{suffix} {p.evals_per_s:.1f} evals/s')
            print(f'BENCH map_worker_utilisation{suffix} {100 * p.utilisation:.1f} %')
        rng = np.random.default_rng(0)
        big = Archive(
            rng.random((40000, 6)),
            rng.random(40000),
            rng.random((40000, 6)),
            rng.random((40000, 32)),
        )
        t0 = time.perf_counter()
        big.save(Path(tmp) / 'big.npz')
        print(f'BENCH map_archive_save_ms {(time.perf_counter() - t0) * 1e3:.0f} ms')


def bench_adapt() -> None:
    """
    Adaptation benchmarks.

    adapt_mboa_step_ms: one M-BOA step (observe a trial + pick the next gait) on a 40 000-gait map
    after 19 trials (median of 20 runs' last steps). adapt_prior_rescore_s: the default map
    re-scored under a damage no cache holds (leg 3 locked), 2 processes. Then thesis experiment 5.2
    on the default map (``BENCH_ADAPT_MAP`` overrides it): every orientation of S1-S4, with trials
    on the map's engine and again across engines (suffix _cross), in three setups: the default
    profile (no suffix; the damaged control tripod is each run's success floor), the default
    profile starting from the damage-informed prior (suffix _prior), and the thesis profile (suffix
    _thesis; the thesis rule, no floor). Per run: the best speed found, the trials, the control
    tripod with the same damage, and the ratio to the map's ceiling under the damage (cached
    ceilings only; across engines, approximate PyBullet ceilings if cached -- none are shipped:
    studies/adaptation/README.md, "Regret against the ceiling", says why). Runs end by M-BOA's
    stopping rule, capped at the budget users get (24 trials), and for the thesis profile at
    EXPERIMENT_MAX_TRIALS (100) so that its rule ends them. Trials are 5 s from standing (the
    product's and the thesis's trial), with adapt_node's tip guard (a trial that tilts the body
    past 30 deg scores 0; adapt_tipped_trials counts them). Then the default profile, blind
    (_judge) and from the damage-informed prior (_prior_judge), with trials on the judge engine
    (DART).
    """
    import os
    from pathlib import Path

    from hexapod_adapt.mapping.archive import load_archive
    from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_ceilings, shipped_map
    from hexapod_adapt.mapping.simulation import archive_engine
    from hexapod_adapt.online.adaptation import DEFAULT_TIP_GUARD, run_experiment
    from hexapod_adapt.online.ceiling import (
        approximate_ceiling,
        approximate_key,
        cache_path,
        cached_ceiling,
        ceiling,
        ceiling_key,
    )
    from hexapod_adapt.online.mboa import Mboa, MboaConfig, PROFILES, TRIAL_BUDGET
    from hexapod_sim import ENGINES
    from hexapod_sim.scenarios import scenario
    from hexapod_sim.simulator import JUDGE_ENGINE

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

    path = Path(os.environ.get('BENCH_ADAPT_MAP', shipped_map(DEFAULT_MAP)))
    print(f'# experiment on {path}', file=sys.stderr)
    archive = load_archive(path)
    print(f'BENCH adapt_map_gaits {archive.n_filled} gaits')
    map_engine = archive_engine(archive.metadata) or 'pybullet'
    other = next(e for e in ENGINES if e != map_engine)
    cached = shipped_ceilings()
    # the damage-informed prior: the whole map re-scored under a damage no cache holds, as
    # adapt_node does before a run (2 processes, the project machine's cores)
    import tempfile

    from hexapod_adapt.online.prior import damage_prior
    from hexapod_sim.damage import Damage

    with tempfile.TemporaryDirectory() as scratch:
        prior = damage_prior(archive, Damage.of('locked', [3]), map_engine, scratch, workers=2)
    print(f'BENCH adapt_prior_rescore_s {prior.seconds:.1f} s')
    # the streaming prior: the time until the top of the map is re-scored and the first trial
    # may start (the rest streams in between trials), same damage, no cache
    from hexapod_adapt.online.streaming_prior import StreamingPrior

    with tempfile.TemporaryDirectory() as scratch:
        t0 = time.monotonic()
        stream = StreamingPrior(archive, Damage.of('locked', [3]), map_engine, scratch, workers=2)
        stream.wait_first(600)
        print(f'BENCH adapt_prior_first_trial_s {time.monotonic() - t0:.1f} s')
        stream.close()
    legs_all = [legs for name in ('S1', 'S2', 'S3', 'S4') for legs in scenario(name)]

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
    setups = [('', 'default', True, False), ('_thesis', 'thesis', False, False)]
    if have_priors:
        setups.insert(1, ('_prior', 'default', True, True))
    for engine, cross in ((map_engine, ''), (other, '_cross')):
        # cached ceilings only: a missing PyBullet ceiling costs many minutes of a core
        have = all(cache_path(cached, key(legs, engine)).is_file() for legs in legs_all)
        for label, name, floor, informed in setups:
            suffix = label + cross
            config = PROFILES[name]
            rows = run_experiment(
                archive,
                config=replace(config, max_trials=100 if name == 'thesis' else TRIAL_BUDGET),
                trial_engine=engine,
                ceilings=ceilings if have else None,
                floor=floor,
                priors=priors if informed else None,
                setup=name + ('+prior' if informed else ''),
                tip_guard=DEFAULT_TIP_GUARD,
            )
            _print_experiment(rows, suffix, have, engine, cached)
    # the judge: trials walked on the engine that takes no part in making or tuning anything
    if map_engine != JUDGE_ENGINE:
        for label, informed in (('', False), ('_prior', True)):
            if informed and not have_priors:
                continue
            rows = run_experiment(
                archive,
                config=replace(PROFILES['default'], max_trials=TRIAL_BUDGET),
                trial_engine=JUDGE_ENGINE,
                floor=True,
                priors=priors if informed else None,
                setup='default' + ('+prior' if informed else ''),
                tip_guard=DEFAULT_TIP_GUARD,
            )
            _print_experiment(rows, f'{label}_judge', False, JUDGE_ENGINE, cached)
    _bench_damage_kinds(archive, map_engine, cached, legs_all)


def _bench_damage_kinds(archive, map_engine: str, cached, legs_all) -> None:
    """
    Adaptation on every damage kind (issue 31): the default profile, blind and with the prior.

    Per kind K: adapt_beats_control_<K> (of the 21 S1-S4 cases), adapt_speed_mean_<K> and, where
    the shipped cache holds the kind's 21 ceilings, adapt_ceiling_ratio_median_<K> and _min_<K>;
    the same with the damage-informed prior (suffix _prior), which needs those ceilings.
    """
    from hexapod_adapt.online.adaptation import run_experiment
    from hexapod_adapt.online.ceiling import cached_ceiling, ceiling
    from hexapod_adapt.online.mboa import PROFILES, TRIAL_BUDGET
    from hexapod_sim.damage import Damage, EXPERIMENT_KINDS

    config = replace(PROFILES['default'], max_trials=TRIAL_BUDGET)
    for kind in EXPERIMENT_KINDS:
        damages = [Damage.of(kind, legs) for legs in legs_all]
        have = all(cached_ceiling(archive, d, map_engine, [cached]) is not None for d in damages)
        if not have:
            print(f'# no cached ceilings of kind {kind}: no ratios, no prior', file=sys.stderr)

        def ceilings(damage, engine):
            return ceiling(archive, damage, engine, cached)

        for suffix, informed in (('', False), ('_prior', True)):
            if informed and not have:
                continue
            rows = run_experiment(
                archive,
                config=config,
                ceilings=ceilings if have else None,
                floor=True,
                priors=(lambda d: ceilings(d, map_engine).speeds) if informed else None,
                setup='default' + ('+prior' if informed else ''),
                kind=kind,
            )
            best = np.array([r.best_speed for r in rows])
            control = np.array([r.control_speed for r in rows])
            name = f'{kind}{suffix}'
            beats = int(np.sum(best > control))
            print(f'BENCH adapt_beats_control_{name} {beats} of {len(rows)} runs')
            print(f'BENCH adapt_speed_mean_{name} {best.mean():.3f} m/s')
            print(f'BENCH control_speed_mean_{name} {control.mean():.3f} m/s')
            if have:
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


def _not_yet(area: str):
    def run() -> None:
        print(f'# no {area} benchmarks yet', file=sys.stderr)

    return run


def bench_navigate() -> None:
    """
    Navigation benchmarks (issue 18; docs/navigation.md).

    The navigation experiment on the shipped repertoire and its damage bank, once, with the goals
    of seed 0: navigate_success_<scenario>_<method> [%], navigate_walking_s_median_<scenario>
    (the repertoire with learning, reached goals), navigate_walking_s_median_damaged (S1-S4
    pooled) and its ratio to the intact median; the same for the repertoire with each case's own
    damage left out of the bank (suffix _leaveout: damage the bank does not hold); then dead
    reckoning from the bridge's trial odometry on the emulator (PyBullet, Xsens-like noise) over
    20 consecutive 2 s repertoire steps:
    navigate_odometry_step_error_m (median |estimate - truth| of one step),
    navigate_odometry_yaw_error_rad (RMS) and navigate_odometry_drift_m_after_<k> (k = 5, 10, 20).
    Per damage kind K and scenario S (5 goals per case, navigate and the tripod only):
    navigate_success_<S>_<K>, navigate_tripod_success_<S>_<K> and navigate_time_vs_tripod_<S>_<K>
    (median walking times on the goals both reached).
    """
    from hexapod_adapt.mapping.archive import load_archive
    from hexapod_bridge.emulator.consecutive import dead_reckoning
    from hexapod_navigation.offline.experiment import (
        METHODS,
        NavigationSettings,
        run_navigation,
        summarise,
        versus_tripod,
    )
    from hexapod_navigation.core.repertoire import Repertoire, shipped_repertoire
    from hexapod_navigation.core.specialists import shipped_specialists
    from hexapod_navigation.core.step_bank import shipped_step_bank
    from hexapod_sim import create_simulator
    from hexapod_sim.damage import EXPERIMENT_KINDS

    path = shipped_repertoire()
    for suffix, methods, leave_out in (('', METHODS, False), ('_leaveout', ('repertoire',), True)):
        settings = NavigationSettings(
            repertoire=path,
            goal_seed=0,
            methods=methods,
            bank=shipped_step_bank(),
            leave_out=leave_out,
            specialists=shipped_specialists(),
        )
        rows, _ = run_navigation(settings, workers=2)
        for s in summarise(rows):
            name = f'{s.scenario}_{s.method}{suffix}'
            print(f'BENCH navigate_success_{name} {100 * s.success_rate:.1f} %')
            if s.method == 'repertoire':
                print(
                    f'BENCH navigate_walking_s_median_{s.scenario}{suffix}'
                    f' {s.median_walking_time:.1f} s'
                )
        ours = [r for r in rows if r.method == 'repertoire' and r.reached]
        intact = np.median([r.walking_time for r in ours if r.scenario == 'S0'])
        damaged = np.median([r.walking_time for r in ours if r.scenario != 'S0'])
        print(f'BENCH navigate_walking_s_median_damaged{suffix} {damaged:.1f} s')
        print(f'BENCH navigate_walking_time_ratio_damaged_intact{suffix} {damaged / intact:.2f} x')
    # every damage kind (issue 31): navigate against the steered tripod, 5 goals per case
    for kind in EXPERIMENT_KINDS:
        settings = NavigationSettings(
            repertoire=path,
            scenarios=('S1', 'S2', 'S3', 'S4'),
            goals=5,
            goal_seed=0,
            methods=('repertoire', 'tripod'),
            bank=shipped_step_bank(),
            damage_kind=kind,
            specialists=shipped_specialists(),
        )
        for v in versus_tripod(run_navigation(settings, workers=2)[0]):
            name = f'{v.scenario}_{kind}'
            print(f'BENCH navigate_success_{name} {100 * v.success:.1f} %')
            print(f'BENCH navigate_tripod_success_{name} {100 * v.tripod_success:.1f} %')
            print(f'BENCH navigate_time_vs_tripod_{name} {v.time_ratio:.2f} x')
    repertoire = Repertoire.from_archive(load_archive(path))
    picks = np.random.default_rng(0).choice(len(repertoire), 20, replace=False)
    with create_simulator() as sim:
        d = dead_reckoning(sim, [repertoire.gait(int(i)) for i in picks], 2.0, seed=1)
    print(f'BENCH navigate_odometry_step_error_m {np.median(d.step_errors):.4f} m')
    yaw_rms = float(np.sqrt(np.mean(np.square(d.yaw_errors))))
    print(f'BENCH navigate_odometry_yaw_error_rad {yaw_rms:.4f} rad')
    for k in (5, 10, 20):
        print(f'BENCH navigate_odometry_drift_m_after_{k} {d.drift[k - 1]:.4f} m')


def bench_firmware() -> None:
    """
    The C++ firmware module (issue 20; firmware/INTEGRATION.md).

    The STM32F407 cross build's flash and RAM; with qemu-system-arm installed, instruction counts
    on QEMU's Cortex-M4 board (startup, one frame, a COMMIT of a 1 s gait, the worst COMMIT) and
    the time per table row at 168 MHz; then the differential fuzz's rate on this machine
    (firmware_fuzz_frames_per_s, 20,000 frames, seed 0).
    """
    import os
    from pathlib import Path
    import shutil
    import subprocess
    import tempfile

    from hexapod_bridge.emulator.differential import fuzz

    root = Path(__file__).resolve().parents[1]
    target = 'arm-counts' if shutil.which('qemu-system-arm') else 'arm'
    if target == 'arm':
        print('# qemu-system-arm not installed: no instruction counts', file=sys.stderr)
    with tempfile.TemporaryDirectory() as build:
        out = subprocess.run(
            ['make', '-s', '-C', str(root / 'firmware'), target, f'BUILD={build}'],
            capture_output=True,
            text=True,
            check=True,
            env=os.environ,
        ).stdout
    print('\n'.join(line for line in out.splitlines() if line.startswith(('BENCH', '#'))))
    result = fuzz(seed=0, frames=20_000)
    if result.divergence is not None:
        raise SystemExit(f'the firmware module diverged from the model: {result.divergence}')
    print(f'BENCH firmware_fuzz_frames_per_s {result.frames / result.seconds:.0f} frames/s')


AREAS = {
    'gait': bench_gait,
    'sim': bench_sim,
    'map': bench_map,
    'adapt': bench_adapt,
    'bridge': bench_bridge,
    'navigate': bench_navigate,
    'firmware': bench_firmware,
}


def main(argv: list[str]) -> int:
    if len(argv) != 1 or argv[0] not in list(AREAS) + ['all']:
        print(f'usage: bench.py {{all|{"|".join(AREAS)}}}', file=sys.stderr)
        return 2
    for name in AREAS if argv[0] == 'all' else [argv[0]]:
        AREAS[name]()
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
