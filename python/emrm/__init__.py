"""emrm from Python: the verification and validation toolkit of an Evasive Minimum-Risk Maneuver.

Every number comes from the C++ library the ``emrm`` command line calls (the extension module
``emrm._emrm``); this package adds the pandas tables and plain-Python conveniences around it.
A short tour is in docs/python.md::

    import emrm
    cell = emrm.simulate(speed_kph=60, ttc_s=0.8)           # as `emrm simulate --json`
    cell.region, cell.strategies["dodge"].trajectory.x      # 'Y', a NumPy array (no copy)
    results = emrm.sweep("examples/tjunction/campaign.yaml", "out/campaign")
    results.cells                                           # pandas, as cells.csv
"""

from __future__ import annotations

import ast
import functools
import inspect
import os
import re
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping, Optional, Union

from . import _emrm
from ._emrm import (
    ActuationConfig,
    CarBody,
    CellResult,
    ControllerConfig,
    Error,
    CrossingConfig,
    CutInConfig,
    FsmReport,
    HighwayConfig,
    InputError,
    Interrupted,
    ObstacleConfig,
    Outcome,
    PlannerConfig,
    RoadConfig,
    RoadsideConfig,
    SafeStateConfig,
    Scene,
    SeverityConfig,
    SimulationConfig,
    Trajectory,
    TruckConfig,
    UsageError,
    VehicleParams,
    __version__,
    check_covering_array,
    check_fsm,
    covering_array,
    merge,
    simulate,
    strategy_names,
)

if TYPE_CHECKING:
    import pandas

PathLike = Union[str, "os.PathLike[str]"]


# ---- signatures ----------------------------------------------------------------------------
# The extension's functions are builtins, which inspect.signature cannot read: IDEs, Jupyter's
# hints and help() showed none. pybind11 writes each one's signature as the first line of its
# docstring, from the C++ argument list (their one owner); these Python functions forward to them
# and carry that line as their __signature__.


class _Default:
    """A default that is not a Python literal, shown as pybind11 spells it."""

    def __init__(self, text: str) -> None:
        self.text = text

    def __repr__(self) -> str:
        return self.text


def _documented_signature(function: Any) -> Optional[inspect.Signature]:
    """The signature the first line of a pybind11 docstring gives, or None (overloads, no doc)."""
    line = (function.__doc__ or "").split("\n", 1)[0]
    match = re.fullmatch(r"\w+\((.*)\)(?:\s*->\s*(.+))?", line)
    if not match:
        return None
    try:
        tree = ast.parse(f"def _f({match.group(1)}): pass")
    except SyntaxError:
        return None
    args = tree.body[0].args  # type: ignore[attr-defined]

    def annotation(node: Optional[ast.expr]) -> Any:  # pybind11's "handle" and "object": any
        text = "" if node is None else ast.unparse(node)
        return inspect.Parameter.empty if text in ("", "handle", "object") else text

    def default(node: ast.expr) -> Any:
        try:
            return ast.literal_eval(node)
        except ValueError:
            return _Default(ast.unparse(node))

    P = inspect.Parameter
    parameters = []
    positional = args.posonlyargs + args.args
    first_default = len(positional) - len(args.defaults)
    for i, a in enumerate(positional):
        kind = P.POSITIONAL_ONLY if i < len(args.posonlyargs) else P.POSITIONAL_OR_KEYWORD
        d = default(args.defaults[i - first_default]) if i >= first_default else P.empty
        parameters.append(P(a.arg, kind, default=d, annotation=annotation(a.annotation)))
    if args.vararg:
        parameters.append(P(args.vararg.arg, P.VAR_POSITIONAL, annotation=annotation(args.vararg.annotation)))
    for a, d in zip(args.kwonlyargs, args.kw_defaults):
        parameters.append(
            P(a.arg, P.KEYWORD_ONLY, default=P.empty if d is None else default(d), annotation=annotation(a.annotation))
        )
    if args.kwarg:
        parameters.append(P(args.kwarg.arg, P.VAR_KEYWORD, annotation=annotation(args.kwarg.annotation)))
    returns = match.group(2)
    return inspect.Signature(parameters, return_annotation=returns if returns else inspect.Signature.empty)


def _with_signature(function: Any) -> Any:
    """`function` (an extension builtin) behind a Python function that inspect.signature reads."""
    signature = _documented_signature(function)
    if signature is None:
        return function

    @functools.wraps(function)
    def forward(*args: Any, **kwargs: Any) -> Any:
        return function(*args, **kwargs)

    forward.__signature__ = signature  # type: ignore[attr-defined]
    return forward


def _with_method_signatures(cls: type) -> None:
    """The extension class `cls` with each of its own methods behind a _with_signature function."""
    for name, member in list(vars(cls).items()):
        if isinstance(member, staticmethod):
            wrapped = _with_signature(member.__func__)
            if wrapped is not member.__func__:
                setattr(cls, name, staticmethod(wrapped))
        elif type(member).__name__ == "instancemethod" and (name == "__init__" or not name.startswith("_")):
            wrapped = _with_signature(member.__func__)
            if wrapped is not member.__func__:
                setattr(cls, name, wrapped)


for _class in vars(_emrm).values():
    if isinstance(_class, type) and _class.__module__ == _emrm.__name__ and not issubclass(_class, BaseException):
        _with_method_signatures(_class)

check_covering_array = _with_signature(check_covering_array)
check_fsm = _with_signature(check_fsm)
covering_array = _with_signature(covering_array)
merge = _with_signature(merge)
simulate = _with_signature(simulate)
strategy_names = _with_signature(strategy_names)

__all__ = [
    "ActuationConfig", "Analysis", "CarBody", "CellResult", "ControllerConfig", "CrossingConfig", "CutInConfig", "Error", "FindingsError", "FsmReport", "HighwayConfig",
    "InputError", "Interrupted", "ObstacleConfig", "Outcome", "Plan", "PlannerConfig", "Results", "RoadConfig", "RoadsideConfig",
    "SafeStateConfig", "Scene", "SeverityConfig", "SimulationConfig", "Trajectory", "TruckConfig",
    "UsageError", "VehicleParams", "__version__", "analyze", "check_covering_array", "check_fsm",
    "covering_array", "covering_array_model", "load_results", "merge", "plan", "simulate",
    "strategy_names", "sweep",
]


def _frame(columns: Mapping[str, Any]) -> "pandas.DataFrame":
    import pandas  # on first use: simulate and covering_array need NumPy alone

    return pandas.DataFrame(dict(columns))


# ---- sweeps and results ------------------------------------------------------------------


@dataclass
class Results:
    """A results folder (docs/campaign.md) as pandas tables, at full precision.

    cells: one row per feasible cell and strategy, the columns of cells.csv in their order (the
    cell's index after grid), then every other field of the outcome record in the order of its
    field list (docs/architecture.md: contact, p_mais3, p_fatal, planner_nodes, planner_rollouts,
    fsm_trace, loss_evaluation_trace, chosen_strategy, adopted_from, maneuver) and the cell's seed.
    regions: one row per cell, the columns of regions.csv in their order (index after grid; the harm
    reductions NaN where it leaves them blank), then every other field of the cell record in its
    list's order (seed, the unmitigated reference, strengthened, certificate, inferred_from).
    Lists (traces, inferred_from) are words separated by spaces; a field added to a record is a
    column here too.
    kpis: the rows of tables/kpis.csv (campaign::grid_kpis).
    ``results["cells"]`` reads as ``results.cells``.
    """

    cells: "pandas.DataFrame"
    regions: "pandas.DataFrame"
    kpis: "pandas.DataFrame"
    meta: dict = field(default_factory=dict)  # config_hash, seed, strategies, grids, the campaign and scene YAML
    adaptive: dict = field(default_factory=dict)  # grid -> the adaptive search's summary (docs/adaptive.md)
    dir: Optional[Path] = None  # the folder, or None for a sweep into a temporary one
    summary: Optional[dict] = None  # a sweep's: cells_total, cells_done_before, cells_simulated, seconds, adaptive

    def __getitem__(self, table: str) -> "pandas.DataFrame":
        if table not in ("cells", "regions", "kpis"):
            raise KeyError(table)
        return getattr(self, table)


def load_results(dir: PathLike) -> Results:
    """The results folder `dir` (written by emrm.sweep, `emrm sweep`, `merge`, `run` or `reproduce`)
    as pandas DataFrames. Raises UsageError when it holds no results store."""
    tables = _emrm._read_results(dir)
    return Results(
        cells=_frame(tables["cells"]),
        regions=_frame(tables["regions"]),
        kpis=_frame(tables["kpis"]),
        meta=tables["meta"],
        adaptive=tables["adaptive"],
        dir=Path(dir),
    )


def sweep(
    campaign: Union[PathLike, Mapping[str, Any]],
    out_dir: Optional[PathLike] = None,
    threads: int = 0,
    progress: bool = True,
    *,
    profile: Optional[str] = None,
    force: bool = False,
    shard: str = "1/1",
    adaptive: bool = False,
    verify_sample: Optional[int] = None,
    initial_levels: Optional[int] = None,
    stride: Optional[int] = None,
    brackets: Optional[str] = None,
    spread: Optional[int] = None,
    progress_log: Optional[PathLike] = None,
) -> Results:
    """Sweeps a campaign (a file, or a mapping shaped like one; docs/campaign.md) into `out_dir`, as
    `emrm sweep CAMPAIGN -o OUT_DIR` does, and returns its results.

    The GIL is released while the cells run on `threads` threads (0: every core); the results do not
    depend on the count. Sweeping into a folder that holds part of the same campaign resumes it.
    Ctrl-C stops the sweep once the cells in flight are stored and raises emrm.Interrupted (a
    KeyboardInterrupt); calling sweep again resumes it. Without `out_dir` the sweep runs in a
    temporary folder, removed once read. The keywords are `emrm sweep`'s options: --profile,
    --force, --shard, --adaptive, --verify-sample (None: automatic), --initial-levels, --stride,
    --brackets ("auto", "search" or "predict"), --spread, --progress-log; the adaptive search's
    left at None take the command's defaults. `progress` draws the bar on stderr when it is a terminal.
    """
    args = (threads, progress, profile, force, shard, adaptive, progress_log)
    search = {"initial_levels": initial_levels, "stride": stride, "brackets": brackets, "spread": spread}
    search = {key: value for key, value in search.items() if value is not None}
    search["verify_sample"] = verify_sample
    if out_dir is None:
        with tempfile.TemporaryDirectory(prefix="emrm-sweep-") as folder:
            summary = _emrm._sweep(campaign, folder, *args, **search)
            results = load_results(folder)
        results.dir = None
    else:
        summary = _emrm._sweep(campaign, out_dir, *args, **search)
        results = load_results(out_dir)
    results.summary = summary
    return results


# ---- safety analysis ---------------------------------------------------------------------


@dataclass
class Analysis:
    """A checked safety case (docs/safety-yaml.md), as `emrm analyze` reports it.

    findings: one row per finding (findings.json's fields); traceability: traceability.csv;
    asil: asil.csv; errors and warnings: how many findings of each; to_dict() and to_text(): what
    `emrm analyze --format json` and `emrm analyze` print; write(dir) writes the four files of
    `emrm analyze -o DIR` and returns their paths.
    """

    errors: int
    warnings: int
    findings: "pandas.DataFrame"
    traceability: "pandas.DataFrame"
    asil: "pandas.DataFrame"
    _analysis: Any = field(repr=False)

    @classmethod
    def _of(cls, analysis: Any) -> "Analysis":
        import pandas

        findings = pandas.DataFrame(
            analysis.findings, columns=["code", "severity", "subject", "message", "file", "line", "column"]
        )
        return cls(
            errors=analysis.errors,
            warnings=analysis.warnings,
            findings=findings,
            traceability=_frame(analysis.traceability),
            asil=_frame(analysis.asil),
            _analysis=analysis,
        )

    def to_dict(self) -> dict:
        return self._analysis.to_dict()

    def to_text(self) -> str:
        return self._analysis.to_text()

    def write(self, dir: PathLike) -> list:
        return [Path(p) for p in self._analysis.write(dir)]


def analyze(safety: PathLike, fsm: Optional[PathLike] = None, no_fsm: bool = False) -> Analysis:
    """Checks a safety case as `emrm analyze SAFETY [--fsm FSM | --no-fsm]` does: its UCAs'
    transitions against `fsm`, else against the case's own `fsm:` entry (neither with no_fsm).
    Raises InputError at the file's line and column for a malformed case."""
    return Analysis._of(_emrm._analyze(safety, fsm, no_fsm))


# ---- scenarios ---------------------------------------------------------------------------


class FindingsError(Exception):
    """emrm.plan refused an ODD whose safety case has error findings (`emrm plan` exits 1);
    .analysis holds them. plan(..., allow_findings=True) plans anyway."""

    def __init__(self, message: str, analysis: Analysis):
        super().__init__(message)
        self.analysis = analysis


@dataclass
class Plan:
    """The minimum scenario set of an ODD (docs/plan.md), as `emrm plan` writes it.

    scenarios: scenarios.csv (values at full precision); coverage: coverage.csv (one row per
    metric, one column per scenario set: the plan, then the baselines); coverage_json and
    plan_json: coverage.json and scenarios.json; satisfied: the independent checker finds C1-C4
    (`emrm plan` exits 0); targets_met: the construction met C1-C4 and the precision target;
    warnings: the cross-file checks' warnings; text: what `emrm plan` prints; analysis: the safety
    case's, when the ODD names one.
    """

    scenarios: "pandas.DataFrame"
    coverage: "pandas.DataFrame"
    coverage_json: dict
    plan_json: dict
    satisfied: bool
    targets_met: bool
    warnings: list
    text: str
    analysis: Optional[Analysis] = None


def plan(
    odd: Union[PathLike, Mapping[str, Any]],
    safety: Optional[PathLike] = None,
    out_dir: Optional[PathLike] = None,
    allow_findings: bool = False,
) -> Plan:
    """Builds the minimum scenario set of an ODD (a file, or a mapping shaped like one) as
    `emrm plan ODD [--safety SAFETY] [-o OUT_DIR] [--allow-findings]` does: the ODD checked
    against the scene and the safety case first, the five files written to `out_dir` when given.
    Raises FindingsError when the safety case has error findings, unless allow_findings."""
    out = _emrm._plan(odd, safety, out_dir, allow_findings)
    analysis = Analysis._of(out["analysis"]) if "analysis" in out else None
    if "scenarios" not in out:
        raise FindingsError(
            f"the safety case has {analysis.errors} error finding(s); no plan (fix them, or plan anyway "
            "with allow_findings=True)",
            analysis,
        )
    return Plan(
        scenarios=_frame(out["scenarios"]),
        coverage=_frame(out["coverage_table"]),
        coverage_json=out["coverage"],
        plan_json=out["plan"],
        satisfied=out["satisfied"],
        targets_met=out["targets_met"],
        warnings=out["warnings"],
        text=out["text"],
        analysis=analysis,
    )


def covering_array_model(
    model: PathLike,
    strength: int = 2,
    *,
    seed: int = 1,
    effort: float = 10.0,
    max_tuples: int = 20_000_000,
    max_search_steps: int = 10_000_000,
) -> "pandas.DataFrame":
    """The covering array of a PICT-style model file (docs/covering-arrays.md), as `emrm ca MODEL`
    prints it: one column per parameter, its values as the model writes them (numbers where every
    value of the parameter is one)."""
    import pandas

    frame = _frame(_emrm._covering_array_model(model, strength, seed, effort, max_tuples, max_search_steps))
    for column in frame.columns:
        try:
            frame[column] = pandas.to_numeric(frame[column])
        except (ValueError, TypeError):
            pass  # a parameter with a value that is not a number stays text
    return frame
