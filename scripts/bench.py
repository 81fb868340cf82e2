#!/usr/bin/env python3
# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Benchmarks. Each figure is printed on its own line as ``BENCH <name> <value> <unit>``.

python scripts/bench.py all|gait|sim|map|adapt|bridge|navigate|firmware
"""

from __future__ import annotations

import importlib.util
import os
from pathlib import Path
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
    _gil_wait(dart)
    bench_converged()


def _gil_wait(sim) -> None:
    """
    Print sim_loop_gil_wait_ms: what a thread waits for the GIL while a loop runs flat out.

    The median wall time of ``time.sleep(0)`` (it gives up the GIL and takes it back) in another
    thread while a PhysicsLoop steps ``sim`` as fast as possible: what every syscall or rcl call
    of sim_node's executor pays (Python's default switch interval: ~5 ms).
    """
    import statistics

    from hexapod_gait import build_joint_table, preset
    from hexapod_sim.physics.physics_loop import LoopHooks, PhysicsLoop
    from hexapod_sim.trajectory_input import CycleTable

    table = build_joint_table(preset('tripod'), rate=1.0 / sim.dt)

    def nothing(*_):
        return False

    hooks = LoopHooks(nothing, nothing, nothing, nothing, nothing)
    loop = PhysicsLoop(sim, CycleTable(table.positions, table.velocities, sim.dt), hooks, rtf=0.0)
    loop.start()
    waits = []
    for _ in range(200):
        t0 = time.perf_counter()
        time.sleep(0)
        waits.append(time.perf_counter() - t0)
    loop.stop()
    print(f'BENCH sim_loop_gil_wait_ms {statistics.median(waits) * 1e3:.3f} ms')


def bench_converged() -> None:
    """
    MuJoCo's converged evaluation against today's 4 steps per row and the 8-step reference.

    On the default map's 300 fastest and 100 other gaits (``BENCH_CONVERGED_GAITS``, 'F,R'),
    5 s, collisions not fatal, batches of 8 interleaved across the three settings on the core
    bench_sim pinned: sim_eval_mujoco_converged_ms (``SimConfig.converged``, per gait),
    sim_converged_cost_ratio (converged / 4 steps per row), sim_eval_mujoco_8step_ms, and the
    converged setting's agreement with 8 steps per row: sim_converged_speed_mad (median |speed
    change|) and sim_converged_spearman (studies/engines/converged_cost.py, the whole study).
    """
    from dataclasses import replace

    from hexapod_adapt.mapping.archive import load_archive
    from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map
    from hexapod_adapt.mapping.transfer import ranked_gaits
    from hexapod_sim import create_simulator, evaluate_gaits, SimConfig
    from hexapod_sim.engine_settings import DEFAULT_SETTINGS
    from scipy.stats import spearmanr

    fastest, others = (
        int(x) for x in os.environ.get('BENCH_CONVERGED_GAITS', '300,100').split(',')
    )
    archive = load_archive(shipped_map(DEFAULT_MAP))
    genes = archive.genotypes[ranked_gaits(archive, fastest, others, seed=0)]
    configs = {
        'converged': SimConfig.converged('mujoco'),
        '4': SimConfig('mujoco', mujoco=replace(DEFAULT_SETTINGS, substeps=4)),
        '8': SimConfig('mujoco', mujoco=replace(DEFAULT_SETTINGS, substeps=8)),
    }
    sims = {name: create_simulator(config) for name, config in configs.items()}
    per_gait: dict[str, list[float]] = {name: [] for name in sims}
    speeds: dict[str, list[float]] = {name: [] for name in sims}
    for i in range(0, len(genes), 8):
        batch = list(genes[i : i + 8])
        for name, sim in sims.items():
            t0 = time.process_time()
            speeds[name] += [r.speed for r in evaluate_gaits(batch, sim, collisions_fatal=False)]
            per_gait[name].append((time.process_time() - t0) / len(batch))
    ms = {name: float(np.median(t)) * 1e3 for name, t in per_gait.items()}
    conv, ref = np.array(speeds['converged']), np.array(speeds['8'])
    print(f'BENCH sim_converged_gaits {len(genes)} gaits')
    print(f'BENCH sim_eval_mujoco_converged_ms {ms["converged"]:.1f} ms')
    print(f'BENCH sim_eval_mujoco_8step_ms {ms["8"]:.1f} ms')
    print(f'BENCH sim_converged_cost_ratio {ms["converged"] / ms["4"]:.3f} 1')
    print(f'BENCH sim_converged_speed_mad {np.median(np.abs(conv - ref)):.4f} m/s')
    print(f'BENCH sim_converged_spearman {spearmanr(conv, ref).statistic:.4f} 1')


def bench_bridge() -> None:
    """
    bridge_parse_frames_per_s.

    Robot->PC frames (extension reports) the host parser decodes per second; bridge_upload_ms: one
    gait upload (35 SET_PARAM + COMMIT, acknowledged) over an emulated clean 19200-baud link,
    emulated time; bridge_link_down_max_ms / bridge_link_up_max_ms: the slowest of 10 radio-port
    losses to be reported, and of 10 returns to bring telemetry back, through the ROS graph.
    """
    from hexapod_bridge.emulator.firmware import RobotFirmware
    from hexapod_bridge.link import RobotLink
    from hexapod_bridge.protocol import extension as ext
    from hexapod_bridge.protocol.stream import HostParser
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

    from hexapod_bridge.emulator.robot_emulator_cli import radio_gone_times
    from hexapod_bridge.ros_conversions import reports_down_since
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


def _bench_map() -> Path:
    """Return the map ``make bench-map`` measures: the shipped default map, or ``BENCH_MAP``."""
    from hexapod_adapt.mapping.maps import DEFAULT_MAP, shipped_map

    return Path(os.environ.get('BENCH_MAP') or shipped_map(DEFAULT_MAP))


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
    from hexapod_adapt.mapping.plots import log_runs

    path = _bench_map()
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
    from hexapod_adapt.mapping.simulation import engine_of_map
    from hexapod_adapt.mapping.transfer import transfer_figures
    from hexapod_sim import create_simulator, ENGINES, SimConfig
    from hexapod_sim.simulator import JUDGE_ENGINE

    archive = load_archive(_bench_map())
    made_on = engine_of_map(archive)
    for engine in (e for e in ENGINES if e != made_on):
        name = 'judge' if engine == JUDGE_ENGINE else engine
        # at its converged step (studies/engines/README.md, "Where the engines differ", item 6)
        with create_simulator(SimConfig.converged(engine)) as sim:
            f = transfer_figures(archive, sim)
        print(f'BENCH map_{name}_top100_speed_median {f.top_speed_median:.3f} m/s')
        print(f'BENCH map_{name}_top100_tipped {f.top_tipped} gaits')
        print(f'BENCH map_{name}_spearman {f.spearman:.3f} 1')


def bench_map() -> None:
    """
    The default map's own figures and those on other engines, then the generator's speed.

    ``BENCH_MAP=path`` measures another map's figures (e.g. one not shipped yet).
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
    """Run the adaptation area, scripts/bench_adapt.py (loaded by path: PYTHONSAFEPATH)."""
    path = Path(__file__).with_name('bench_adapt.py')
    spec = importlib.util.spec_from_file_location('bench_adapt', path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    module.bench_adapt()


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
    from hexapod_navigation.core.repertoire import Repertoire, shipped_repertoire
    from hexapod_navigation.core.specialists import shipped_specialists
    from hexapod_navigation.core.step_bank import shipped_step_bank
    from hexapod_navigation.offline.experiment import (
        METHODS,
        NavigationSettings,
        run_navigation,
        summarise,
        versus_tripod,
    )
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
