"""Type stubs of the extension module emrm._emrm (python/src/*.cpp; docs/python.md).

tests/python/test_stubs.py checks that the classes and fields below are the module's."""

import os
from typing import Any, Callable, Mapping, Optional, Sequence, Union

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
    @property
    def lane_width_m(self) -> float: ...
    @property
    def lanes(self) -> int: ...
    @property
    def shoulder_m(self) -> float: ...
    @property
    def ego_lane_center_m(self) -> float: ...

class TruckConfig(_Part):
    @property
    def length_m(self) -> float: ...
    @property
    def width_m(self) -> float: ...
    @property
    def mass_kg(self) -> float: ...
    @property
    def yaw_inertia_kgm2(self) -> float: ...
    @property
    def speed_kph(self) -> float: ...
    @property
    def decel_mps2(self) -> float: ...

class VehicleParams(_Part):
    @property
    def length_m(self) -> float: ...
    @property
    def width_m(self) -> float: ...
    @property
    def mass_kg(self) -> float: ...
    @property
    def yaw_inertia_kgm2(self) -> float: ...
    @property
    def cg_to_front_axle_m(self) -> float: ...
    @property
    def cg_to_rear_axle_m(self) -> float: ...
    @property
    def cg_height_m(self) -> float: ...
    @property
    def max_steer_rad(self) -> float: ...
    @property
    def max_steer_rate_radps(self) -> float: ...
    @property
    def front_cornering_stiffness_n_per_rad(self) -> float: ...
    @property
    def rear_cornering_stiffness_n_per_rad(self) -> float: ...
    @property
    def kinematic_blend_speed_mps(self) -> float: ...

class SimulationConfig(_Part):
    @property
    def vehicle_model(self) -> str: ...
    @property
    def dt_s(self) -> float: ...
    @property
    def horizon_s(self) -> float: ...

class ActuationConfig(_Part):
    @property
    def perception_latency_s(self) -> float: ...
    @property
    def brake_dead_time_s(self) -> float: ...
    @property
    def brake_ramp_s(self) -> float: ...
    @property
    def max_decel_mps2(self) -> float: ...
    @property
    def steer_dead_time_s(self) -> float: ...
    @property
    def steer_time_constant_s(self) -> float: ...

class SeverityConfig(_Part):
    @property
    def restitution(self) -> float: ...
    @property
    def contact_friction(self) -> float: ...
    @property
    def mais3_intercept(self) -> float: ...
    @property
    def mais3_slope_per_mps(self) -> float: ...
    @property
    def fatal_reference_mps(self) -> float: ...
    @property
    def fatal_exponent(self) -> float: ...
    @property
    def l6_p_mais3(self) -> float: ...
    @property
    def l7_p_fatal(self) -> float: ...

class PlannerConfig(_Part):
    @property
    def max_nodes(self) -> int: ...
    @property
    def max_time_ms(self) -> float: ...
    @property
    def min_duration_s(self) -> float: ...
    @property
    def max_duration_s(self) -> float: ...
    @property
    def goal_bias(self) -> float: ...
    @property
    def restarts(self) -> int: ...
    @property
    def plausible_miss_m(self) -> float: ...

class RoadsideConfig(_Part):
    @property
    def type(self) -> str: ...

class SafeStateConfig(_Part):
    @property
    def horizon_s(self) -> float: ...
    @property
    def max_yaw_rate_radps(self) -> float: ...
    @property
    def max_slip_angle_rad(self) -> float: ...
    @property
    def max_heading_error_rad(self) -> float: ...
    @property
    def max_steer_rad(self) -> float: ...

class Scene(_Part):
    """Scene() is the built-in scene; every field of scene.yaml is a read-only attribute."""

    def __init__(self) -> None: ...
    @property
    def name(self) -> str: ...
    @property
    def road(self) -> RoadConfig: ...
    @property
    def truck(self) -> TruckConfig: ...
    @property
    def ego(self) -> VehicleParams: ...
    @property
    def simulation(self) -> SimulationConfig: ...
    @property
    def actuation(self) -> ActuationConfig: ...
    @property
    def severity(self) -> SeverityConfig: ...
    @property
    def planner(self) -> PlannerConfig: ...
    @property
    def roadside(self) -> RoadsideConfig: ...
    @property
    def safe_state(self) -> SafeStateConfig: ...
    @property
    def max_initial_distance_m(self) -> float: ...
    @staticmethod
    def load(path: _Path, profile: Optional[str] = None) -> Scene: ...
    @staticmethod
    def from_dict(mapping: Mapping[str, Any]) -> Scene: ...
    def with_(self, changes: Optional[Mapping[str, Any]] = None, /, **fields: Any) -> Scene: ...
    def with_profile(self, profile: str) -> Scene: ...
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
    @property
    def columns(self) -> tuple[str, ...]: ...
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
    @property
    def strategies(self) -> dict[str, Outcome]: ...
    def to_json(self, indent: int = 2) -> str: ...
    def to_dict(self) -> dict[str, Any]: ...

def simulate(
    scene: _SceneLike = None,
    *,
    speed_kph: float,
    ttc_s: float,
    mu: float = 1.0,
    passage_m: float = 3.0,
    truck_speed_kph: Optional[float] = None,
    strategy: Union[str, Sequence[str], None] = None,
    seed: int = 1,
    certify: bool = True,
    timing: bool = False,
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
    verify_sample: Optional[int],
    initial_levels: int,
    stride: int,
    progress_log: Optional[_Path],
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
