"""PyBullet simulator of the hexapod, gait evaluation and failure scenarios (ROS-free)."""
from hexapod_sim.evaluation import FAILURE_FITNESS, TRIAL_DURATION, EvaluationResult, evaluate_gait
from hexapod_sim.scenarios import SCENARIO_NAMES, all_scenarios, scenario
from hexapod_sim.simulator import (ACCURATE, FAILURE_POSE, FAST, EngineSettings, HexapodSimulator, SimConfig,
                                   validate_failed_legs)

__all__ = ["ACCURATE", "FAILURE_FITNESS", "FAILURE_POSE", "FAST", "SCENARIO_NAMES", "TRIAL_DURATION",
           "EngineSettings", "EvaluationResult", "HexapodSimulator", "SimConfig", "all_scenarios",
           "evaluate_gait", "scenario", "validate_failed_legs"]
