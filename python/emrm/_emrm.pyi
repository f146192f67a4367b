"""Type stubs of the extension module emrm._emrm (python/src/*.cpp; docs/python.md).

tests/python/test_stubs.py checks that the classes and fields below are the module's."""

import os
from typing import Any, Callable, Final, Mapping, Optional, Sequence, TypeAlias, Union

import numpy
import numpy.typing

_Path = Union[str, os.PathLike[str]]
_SceneLike = Union["Scene", _Path, Mapping[str, Any], None]
_Constraints = Union[None, str, Callable[[tuple[int, ...]], bool]]

__version__: str

# ---- errors ---------------------------------------------------------------------------------

class InputError(ValueError):
    """Bad input; str() is the command line's FILE:LINE:COLUMN: error: MESSAGE."""

    file: Optional[str]
    line: Optional[int]
    column: Optional[int]
    message: str
    field: Optional[str]  # the field path of a configuration built in code ("road.lane_width_m")

class UsageError(ValueError): ...
class Error(RuntimeError): ...

class Interrupted(KeyboardInterrupt):
    signal: int

# ---- the scene (docs/scene-yaml.md) ----------------------------------------------------------

class _Part:
    def to_dict(self) -> dict[str, Any]: ...

class RoadConfig(_Part):
    lane_width_m: Final[float]
    lanes: Final[int]
    shoulder_m: Final[float]
    ego_lane_center_m: Final[float]

class ObstacleConfig(_Part):
    length_m: Final[float]
    width_m: Final[float]
    mass_kg: Final[float]
    yaw_inertia_kgm2: Final[float]
    speed_kph: Final[float]
    decel_mps2: Final[float]

TruckConfig: TypeAlias = ObstacleConfig

class VehicleParams(_Part):
    length_m: Final[float]
    width_m: Final[float]
    mass_kg: Final[float]
    yaw_inertia_kgm2: Final[float]
    cg_to_front_axle_m: Final[float]
    cg_to_rear_axle_m: Final[float]
    cg_height_m: Final[float]
    max_steer_rad: Final[float]
    max_steer_rate_radps: Final[float]
    front_cornering_stiffness_n_per_rad: Final[float]
    rear_cornering_stiffness_n_per_rad: Final[float]
    kinematic_blend_speed_mps: Final[float]

class SimulationConfig(_Part):
    vehicle_model: Final[str]
    dt_s: Final[float]
    horizon_s: Final[float]

class ActuationConfig(_Part):
    perception_latency_s: Final[float]
    brake_dead_time_s: Final[float]
    brake_ramp_s: Final[float]
    max_decel_mps2: Final[float]
    steer_dead_time_s: Final[float]
    steer_time_constant_s: Final[float]

class SeverityConfig(_Part):
    restitution: Final[float]
    contact_friction: Final[float]
    mais3_intercept: Final[float]
    mais3_slope_per_mps: Final[float]
    fatal_reference_mps: Final[float]
    fatal_exponent: Final[float]
    l6_p_mais3: Final[float]
    l7_p_fatal: Final[float]
    critical_slope_h: Final[float]
    rollover_p_fatal: Final[float]
    pedestrian_fatal_intercept: Final[float]
    pedestrian_fatal_slope_per_kph: Final[float]
    pedestrian_serious_intercept: Final[float]
    pedestrian_serious_slope_per_kph: Final[float]
    cyclist_serious_intercept: Final[float]
    cyclist_serious_slope_per_kph: Final[float]

class PlannerConfig(_Part):
    max_nodes: Final[int]
    max_time_ms: Final[float]
    min_duration_s: Final[float]
    max_duration_s: Final[float]
    goal_bias: Final[float]
    falsifier_evaluations: Final[int]
    restarts: Final[int]
    plausible_miss_m: Final[float]

class ControllerConfig(_Part):
    max_nodes: Final[int]

class RoadsideConfig(_Part):
    type: Final[str]
    embankment_slope_h: Final[float]

class SafeStateConfig(_Part):
    horizon_s: Final[float]
    max_yaw_rate_radps: Final[float]
    max_slip_angle_rad: Final[float]
    max_heading_error_rad: Final[float]
    max_steer_rad: Final[float]

class HighwayConfig(_Part):
    lanes: Final[int]
    lane_width_m: Final[float]
    shoulder_m: Final[float]
    ego_lane: Final[int]
    embankment_slope_h: Final[float]
    truck: Final[ObstacleConfig]
    deer: Final[ObstacleConfig]

class CrossingConfig(_Part):
    lane_width_m: Final[float]
    parked_gap_m: Final[float]
    parked: Final[ObstacleConfig]
    pedestrian: Final[ObstacleConfig]
    oncoming: Final[ObstacleConfig]

class CarBody(_Part):
    length_m: Final[float]
    width_m: Final[float]
    mass_kg: Final[float]
    yaw_inertia_kgm2: Final[float]

class CutInConfig(_Part):
    lane_width_m: Final[float]
    shoulder_m: Final[float]
    cutting: Final[CarBody]
    brake_delay_s: Final[float]
    follower: Final[CarBody]
    following_gap_s: Final[float]
    follower_faster_kph: Final[float]

class ImportedFactor(_Part):
    parameter: Final[str]
    unit: Final[str]
    min: Final[Optional[float]]
    max: Final[Optional[float]]

class OpenScenarioConfig(_Part):
    file: Final[str]
    ego: Final[str]
    speed_parameter: Final[str]
    factors: Final[list[ImportedFactor]]
    onset_search_s: Final[float]
    handover: Final[str]
    right_roadside: Final[str]
    left_roadside: Final[str]

class Scene(_Part):
    """Scene() is the built-in scene; every field of scene.yaml is a read-only attribute."""

    def __init__(self) -> None: ...
    name: Final[str]
    family: Final[str]
    road: Final[RoadConfig]
    truck: Final[ObstacleConfig]
    ego: Final[VehicleParams]
    simulation: Final[SimulationConfig]
    actuation: Final[ActuationConfig]
    severity: Final[SeverityConfig]
    planner: Final[PlannerConfig]
    controller: Final[ControllerConfig]
    roadside: Final[RoadsideConfig]
    safe_state: Final[SafeStateConfig]
    highway: Final[HighwayConfig]
    crossing: Final[CrossingConfig]
    cut_in: Final[CutInConfig]
    openscenario: Final[OpenScenarioConfig]
    max_initial_distance_m: Final[float]
    @staticmethod
    def load(path: _Path, profile: Optional[str] = None) -> "Scene": ...
    @staticmethod
    def from_dict(mapping: Mapping[str, Any]) -> "Scene": ...
    def with_(self, changes: Optional[Mapping[str, Any]] = None, /, **fields: Any) -> "Scene": ...
    def with_profile(self, profile: str) -> "Scene": ...
    def to_yaml(self) -> str: ...

# ---- one cell (docs/simulate.md) ---------------------------------------------------------------

_Array = numpy.typing.NDArray[numpy.float64]

class Trajectory:
    """Read-only arrays over the result's memory; the truck's has t, x, y, psi only."""

    t: _Array
    x: _Array
    y: _Array
    psi: _Array
    v: _Array
    vx: _Array
    vy: _Array
    yaw_rate: _Array
    steer: _Array
    columns: Final[tuple[str, ...]]
    def __len__(self) -> int: ...
    def __getitem__(self, column: str) -> _Array: ...
    def to_dataframe(self) -> Any: ...

class Outcome:
    """One strategy's outcome: the keys of simulate --json's strategies.NAME."""

    strategy: str
    trajectory: Trajectory
    truck_trajectory: Trajectory
    avoided: bool
    contact: bool
    road_departure: bool
    impact_speed_kph: float
    delta_v_kph: float
    p_mais3: float
    p_fatal: float
    loss_level: int
    departure_speed_kph: float
    evidence: str
    delta_loss: int
    min_ttc_s: Optional[float]
    fsm_trace: list[str]
    loss_evaluation_trace: Optional[list[str]]
    chosen_strategy: Optional[str]
    adopted_from: Optional[str]
    planner: dict[str, Any]
    maneuver: dict[str, Any]
    def to_dict(self) -> dict[str, Any]: ...

class CellResult:
    """One simulated cell: the keys of simulate --json."""

    input: dict[str, Any]
    feasible: bool
    region: str
    evidence: Optional[str]
    mitigation_evidence: Optional[str]
    strengthened: Optional[bool]
    harm_reduction: Optional[dict[str, float]]
    certificate: Optional[dict[str, Any]]
    unmitigated: dict[str, Any]
    strategies: Final[dict[str, Outcome]]
    family: str
    actors: list[dict[str, Any]]
    road: dict[str, Any]
    def to_json(self, indent: int = 2) -> str: ...
    def to_dict(self) -> dict[str, Any]: ...

def simulate(
    scene: _SceneLike = None,
    *,
    strategy: Union[str, Sequence[str], None] = None,
    seed: int = 1,
    certify: bool = True,
    timing: bool = False,
    **factors: float,  # the scene's factors by key (speed_kph and ttc_s required)
) -> CellResult: ...
def strategy_names() -> list[str]: ...

# ---- campaigns (docs/campaign.md; emrm.sweep and emrm.load_results wrap these) ------------------

def _sweep(
    campaign: Union[_Path, Mapping[str, Any]],
    output_dir: _Path,
    threads: int,
    progress: bool,
    profile: Optional[str],
    force: bool,
    shard: str,
    adaptive: bool,
    progress_log: Optional[_Path],
    *,
    verify_sample: Optional[int] = None,
    initial_levels: int = ...,
    stride: int = ...,
    brackets: str = ...,
    spread: int = ...,
) -> dict[str, Any]: ...
def _read_results(dir: _Path) -> dict[str, Any]: ...
def merge(dirs: Sequence[_Path], output_dir: _Path) -> None: ...

# ---- scenarios (docs/covering-arrays.md, docs/plan.md) ----------------------------------------

def covering_array(
    levels: Sequence[int],
    strength: int = 2,
    constraints: _Constraints = None,
    *,
    seed: int = 1,
    effort: float = 10.0,
    max_tuples: int = 20000000,
    max_search_steps: int = 10000000,
) -> numpy.typing.NDArray[numpy.int32]: ...
def check_covering_array(
    levels: Sequence[int],
    strength: int,
    rows: Union[Sequence[Sequence[int]], numpy.typing.NDArray[numpy.int32]],
    constraints: _Constraints = None,
    *,
    max_search_steps: int = 10000000,
) -> dict[str, Any]: ...
def _covering_array_model(
    model: _Path, strength: int, seed: int, effort: float, max_tuples: int, max_search_steps: int
) -> dict[str, list[str]]: ...
def _plan(
    odd: Union[_Path, Mapping[str, Any]], safety: Optional[_Path], output_dir: Optional[_Path], allow_findings: bool
) -> dict[str, Any]: ...

# ---- safety case and FSMs (docs/safety-yaml.md, docs/fsm.md) -----------------------------------

class _Analysis:
    errors: int
    warnings: int
    findings: list[dict[str, Any]]
    traceability: dict[str, list[str]]
    asil: dict[str, list[str]]
    def to_dict(self) -> dict[str, Any]: ...
    def to_text(self) -> str: ...
    def write(self, dir: _Path) -> list[str]: ...

def _analyze(safety: _Path, fsm: Optional[_Path], no_fsm: bool) -> _Analysis: ...

class FsmReport:
    ok: bool
    def to_dict(self) -> dict[str, Any]: ...
    def to_text(self) -> str: ...
    def dot(self) -> str: ...

def check_fsm(
    path: _Path,
    *,
    check: bool = True,
    words: int = -1,
    word: Sequence[str] = (),
    traces: Optional[_Path] = None,
    compose: Optional[_Path] = None,
    max_states: int = 100000,
) -> FsmReport: ...
