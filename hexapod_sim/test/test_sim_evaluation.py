"""Simulator library: determinism, measured footfall, failures, collisions, scenarios."""
from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from hexapod_gait import preset
from hexapod_sim import (FAILURE_POSE, SimConfig, create_simulator, all_scenarios, evaluate_gait, scenario,
                         validate_failed_legs)
from hexapod_sim.sampling import random_reachable_genotypes


@pytest.fixture(scope="module")
def sim():
    with create_simulator(SimConfig()) as s:
        yield s


def _fingerprint(result) -> dict:
    return {"fitness": result.fitness.hex(), "descriptor": [float(v).hex() for v in result.descriptor],
            "valid": result.valid, "reason": result.reason}


FRESH_PROCESS = """
import json, sys
import numpy as np
from hexapod_sim import SimConfig, create_simulator, evaluate_gait
genes = np.array(json.loads(sys.argv[1]))
with create_simulator(SimConfig()) as sim:
    r = evaluate_gait(genes, sim, collisions_fatal=False)
print(json.dumps({"fitness": r.fitness.hex(), "descriptor": [float(v).hex() for v in r.descriptor],
                  "valid": r.valid, "reason": r.reason}))
"""


def test_deterministic_fresh_process_vs_reused_simulator(sim):
    genotypes = random_reachable_genotypes(3, seed=4)
    # warm the reused simulator with other gaits (and a failure) first
    evaluate_gait(preset("wave"), sim, failed_legs=[2])
    sim.set_failed_legs([])
    evaluate_gait(preset("quadruped"), sim)
    for genes in genotypes:
        reused = _fingerprint(evaluate_gait(genes, sim, collisions_fatal=False))
        again = _fingerprint(evaluate_gait(genes, sim, collisions_fatal=False))
        out = subprocess.run([sys.executable, "-c", FRESH_PROCESS, json.dumps(genes.tolist())], check=True,
                             capture_output=True, text=True, env=dict(os.environ)).stdout
        fresh = json.loads(out.strip().splitlines()[-1])
        assert reused == again == fresh


def test_measured_tripod_footfall_alternates_the_two_tripods(sim):
    result = evaluate_gait(preset("tripod"), sim, record_contacts=True)
    contacts = result.contacts[240:].astype(float)     # skip the first cycle (start-up transient)
    corr = np.corrcoef(contacts.T)
    tripods = ([0, 2, 4], [1, 3, 5])
    within = [corr[i, j] for t in tripods for i in t for j in t if i < j]
    across = [corr[i, j] for i in tripods[0] for j in tripods[1]]
    # feet of a tripod go down together; the two tripods alternate (thesis fig. 3.11). Contacts
    # chatter within a stance phase, so compare correlations and majority votes, not "all down".
    assert min(within) > 0.4 and max(across) < -0.4, (within, across)
    a_down = contacts[:, tripods[0]].sum(axis=1) >= 2
    b_down = contacts[:, tripods[1]].sum(axis=1) >= 2
    assert np.mean(a_down & b_down) < 0.15           # only brief overlaps at the switch
    assert a_down.mean() > 0.4 and b_down.mean() > 0.4
    assert result.valid and result.speed > 0.2


@pytest.mark.parametrize("gait,legs", [("wave", (1,)), ("wave", (4,)), ("quadruped", (3,)),
                                       ("quadruped", (2, 5)), ("wave", (1, 3)), ("quadruped", (2, 4))])
def test_failed_leg_holds_its_pose_and_never_touches_the_ground(sim, gait, legs):
    result = evaluate_gait(preset(gait), sim, failed_legs=legs, collisions_fatal=False, record_contacts=True)
    q, _, _ = sim.joint_states()
    for leg in legs:
        assert result.contacts[:, leg - 1].sum() == 0, f"failed leg {leg} touched the ground"
        assert result.descriptor[leg - 1] == 0.0
        np.testing.assert_allclose(q[3 * (leg - 1): 3 * leg], FAILURE_POSE, atol=np.radians(2))
    sim.set_failed_legs([])


def test_scenario_orientation_counts_and_sets():
    counts = {name: len(v) for name, v in all_scenarios().items()}
    assert counts == {"S0": 1, "S1": 6, "S2": 3, "S3": 6, "S4": 6}
    assert scenario("S2") == [(1, 4), (2, 5), (3, 6)]
    assert (1, 6) in scenario("S4") and (1, 2) in scenario("S4")
    assert (1, 5) in scenario("S3") and (2, 4) in scenario("S3")
    with pytest.raises(ValueError, match="unknown failure scenario 'S9'"):
        scenario("S9")


@pytest.mark.parametrize("legs,match", [([7], "leg 7 does not exist"), ([0], "leg 0 does not exist"),
                                        ([1, 2, 3], "at most 2 legs"), (["a"], "integers 1..6"),
                                        ([True], "integers 1..6")])
def test_bad_failed_legs_are_refused_with_a_reason(legs, match):
    with pytest.raises(ValueError, match=match):
        validate_failed_legs(legs)
    assert validate_failed_legs([3, 1, 3]) == (1, 3)


def test_base_dragging_gait_is_flagged(sim):
    low = preset("tripod").replace(body_height=0.04, body_velocity=0.1, step_height=[0.02] * 6)
    result = evaluate_gait(low, sim, collisions_fatal=True)
    assert not result.valid and result.fitness == 0.0 and not result.descriptor.any()
    assert "base_link touched the ground" in result.reason
    relaxed = evaluate_gait(low, sim, collisions_fatal=False)
    assert relaxed.valid and relaxed.collision_steps > 0


def test_self_colliding_gait_is_flagged(sim):
    # legs 1 and 2 turn their foot paths towards each other
    crossed = preset("tripod").replace(angle_offset=[1.5, -1.5, 0, 0, 0, 0])
    result = evaluate_gait(crossed, sim, collisions_fatal=True)
    assert not result.valid and "self-collision" in result.reason
    assert "link_1" in result.reason and "link_2" in result.reason


def test_unreachable_gait_returns_the_failure_value(sim):
    result = evaluate_gait(preset("tripod").replace(radius=[0.3] * 6), sim)
    assert not result.valid and result.fitness == 0.0 and result.reason.startswith("unreachable: leg")


def test_friction_is_configurable():
    with create_simulator(SimConfig(friction=0.05)) as slippery:
        slow = evaluate_gait(preset("tripod"), slippery, collisions_fatal=False).speed
    with create_simulator(SimConfig()) as normal:
        fast = evaluate_gait(preset("tripod"), normal, collisions_fatal=False).speed
    assert slow < 0.5 * fast
    with pytest.raises(ValueError, match="friction"):
        SimConfig(friction=-1)
