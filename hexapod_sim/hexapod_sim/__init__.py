# Copyright 2026 Hexapod adaptation team
# All rights reserved.
#
# Permission is hereby granted, free of charge, to any person obtaining a copy
# of this software and associated documentation files (the "Software"), to deal
# in the Software without restriction, including without limitation the rights
# to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
# copies of the Software, and to permit persons to whom the Software is
# furnished to do so, subject to the following conditions:
#
# The above copyright notice and this permission notice shall be included in all
# copies or substantial portions of the Software.
#
# THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
# IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
# FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
# AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
# LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
# OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
# SOFTWARE.
"""
The hexapod simulator, gait evaluation and failure scenarios (ROS-free).

One simulator interface, three engines: PyBullet, MuJoCo and DART (the judge).
"""

from hexapod_sim.engines import create_simulator
from hexapod_sim.evaluation import (
    evaluate_gait,
    evaluate_gaits,
    EvaluationResult,
    FAILURE_FITNESS,
    TRIAL_DURATION,
)
from hexapod_sim.scenarios import all_scenarios, scenario, SCENARIO_NAMES
from hexapod_sim.simulator import (
    ENGINES,
    FAILURE_POSE,
    JointRows,
    PlayResult,
    SimConfig,
    Simulator,
    StepReport,
    validate_engine,
    validate_failed_legs,
)

__all__ = [
    'ENGINES',
    'FAILURE_FITNESS',
    'FAILURE_POSE',
    'SCENARIO_NAMES',
    'TRIAL_DURATION',
    'EvaluationResult',
    'JointRows',
    'PlayResult',
    'SimConfig',
    'Simulator',
    'StepReport',
    'all_scenarios',
    'create_simulator',
    'evaluate_gait',
    'evaluate_gaits',
    'scenario',
    'validate_engine',
    'validate_failed_legs',
]
