"""The UCT RARL hexapod's URDF and a small API to read it (ROS-free)."""
from hexapod_description.model import (
    HexapodModel,
    JointLimit,
    LegMount,
    N_LEGS,
    load_model,
    parse_model,
    summary,
    urdf_path,
)

__all__ = ["HexapodModel", "JointLimit", "LegMount", "N_LEGS", "load_model", "parse_model",
           "summary", "urdf_path"]
