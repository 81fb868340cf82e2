"""The hexapod simulator (one interface, PyBullet and MuJoCo engines), gait evaluation and
failure scenarios (ROS-free)."""
from hexapod_sim.evaluation import (FAILURE_FITNESS, TRIAL_DURATION, EvaluationResult, evaluate_gait,
                                    evaluate_gaits)
from hexapod_sim.scenarios import SCENARIO_NAMES, all_scenarios, scenario
from hexapod_sim.simulator import (ENGINES, FAILURE_POSE, JointRows, PlayResult, SimConfig, Simulator, StepReport,
                                   create_simulator, validate_engine, validate_failed_legs)

__all__ = ["ENGINES", "FAILURE_FITNESS", "FAILURE_POSE", "SCENARIO_NAMES", "TRIAL_DURATION", "EvaluationResult",
           "JointRows", "PlayResult", "SimConfig", "Simulator", "StepReport", "all_scenarios", "create_simulator",
           "evaluate_gait", "evaluate_gaits", "scenario", "validate_engine", "validate_failed_legs"]
