"""The lab's names, listed once: what a study needs beyond the product's API
(sim_core/__init__.pyi) and the contract (`sim_core.contract`). Type checkers read these
imports; sim_core/research.py loads each name on first use. Each comment says why the name
is public; study code that only the lab runs lives in lab/."""

# `name as name`: an explicit re-export, for type checkers and linters
from .contract.values import (
    BETA_BISTABLE as BETA_BISTABLE,  # what the paper states (scored against)
)
from .contract.values import BETA_FAST as BETA_FAST  # what the paper states (scored against)
from .contract.values import BETA_SLOW as BETA_SLOW  # what the paper states (scored against)
from .contract.values import METACHRONAL_BRANCH as METACHRONAL_BRANCH  # what the paper states
from .contract.values import TRIPOD_BRANCH as TRIPOD_BRANCH  # what the paper states
from .model.anatomy import (
    attachment_points as attachment_points,  # the hips, in the body frame
)
from .model.cpg import (
    advance_phases as advance_phases,  # eq. 1's step (numba), for reduced models
)
from .model.gait import (
    HEADING_KEPT_DEG as HEADING_KEPT_DEG,  # a heading kept within this, deg (slope studies)
)
from .model.gait import (
    angle_diff as angle_diff,  # the signed difference of angles, wrapped (every comparison)
)
from .model.gait import (
    drift_per_cycle as drift_per_cycle,  # Delta31's drift per cycle from the legs' phase jumps
)
from .model.gait import phase_jumps as phase_jumps  # eq. 4's jumps at touchdown, per leg
from .model.gait import (
    window_d31 as window_d31,  # where Delta31 sits now (`window_gait`'s reading; short screens)
)
from .model.gait import yaw_of as yaw_of  # the body's heading from its quaternions
from .model.legs import (
    inverse_kinematics as inverse_kinematics,  # leg kinematics (reach checks)
)
from .model.legs import leg_geometry as leg_geometry  # leg kinematics (reach checks)
from .model.legs import swing_point as swing_point  # leg kinematics (reach checks)
from .model.mjspec import build_model as build_model  # the MjModel, to pose or probe it
from .model.mjspec import (
    leg_qpos_addresses as leg_qpos_addresses,  # pose a `build_model` model
)
from .model.mjspec import (
    mid_stance_angles as mid_stance_angles,  # pose a `build_model` model
)
from .model.params import (
    phi_aep as phi_aep,  # the AEP's phase, 2 pi (1 - beta) (Sec. II B 2)
)
from .model.probes import (
    open_loop_drift as open_loop_drift,  # the drift probe (resets off, D31 held)
)
from .model.runner import (
    BatchRunner as BatchRunner,  # the one run loop, with a per-period hook
)
from .model.settings import (
    NAMED_SETTINGS as NAMED_SETTINGS,  # named regimes of invented parameters
)
from .model.settings import named_params as named_params  # a named regime as ModelParams
from .paper.analysis import (
    branch_ranges as branch_ranges,  # each gait's stable range and folds in the finder's cells
)
from .paper.atlas import AtlasConfig as AtlasConfig  # the finder atlas's grid and protocol
from .paper.atlas import (
    run_atlas as run_atlas,  # the finder over a beta x axis grid, cached, on a backend
)
from .paper.atlas import (
    write_atlas as write_atlas,  # atlas_<axis>.json and .png
)
from .paper.claims import (
    CALIBRATED as CALIBRATED,  # the calibrated parameters (the +-10% checks)
)
from .paper.claims import SCALES as SCALES  # the +-10% checks' scales
from .paper.claims import scaled_values as scaled_values  # the +-10% checks' variants
from .paper.figures import (
    ReproduceConfig as ReproduceConfig,  # `reproduce`'s protocol, to repeat it
)
from .paper.finder_runs import (
    cluster_finals as cluster_finals,  # settled ends clustered as the finder clusters them
)
from .paper.plots import fig5 as fig5  # the reproduction's Fig. 5 drawing of free runs
from .paper.returnmap import (
    initial_values as initial_values,  # the protocols' starts, spread over the circle
)
from .paper.search import (
    probe_task as probe_task,  # a finder run as its cached task (same key)
)
from .paper.search import (
    task_runner as task_runner,  # `find`'s runs as cached tasks on a backend
)
from .paper.surface import (
    assemble as assemble,  # a surface from its probes (re-read under another rule)
)
from .paper.surface import (
    grid_probes as grid_probes,  # a drift surface's first-pass probes
)
from .paper.surface import (
    probe_spec as probe_spec,  # a surface probe's pinned run (read back cached)
)
from .paper.surface import read_probe as read_probe  # a probe's numbers from its cached run
from .runs import BACKENDS as BACKENDS  # the backends' names (cached, resumable runs)
from .runs.tasks import ramp_task as ramp_task  # a ramped run (a sweep) as a cached task
