"""MAP-Elites map generation and M-BOA adaptation for the hexapod (ROS-free library; the nodes
and commands are adapt_node, adapt_client, generate_map and run_experiment)."""
from hexapod_adapt.adaptation import AdaptationResult, TrialAborted, adapt, run_experiment, simulated_trial
from hexapod_adapt.archive import Archive, ArchiveError, import_thesis_map, load_archive
from hexapod_adapt.map_elites import Evaluation, MapElitesConfig, run_map_elites
from hexapod_adapt.mboa import Mboa, MboaConfig

__all__ = ["AdaptationResult", "Archive", "ArchiveError", "Evaluation", "MapElitesConfig", "Mboa", "MboaConfig",
           "TrialAborted", "adapt", "import_thesis_map", "load_archive", "run_experiment", "run_map_elites",
           "simulated_trial"]
