"""emrm.simulate gives what `emrm simulate --json` prints for the same cell, key for key and bit for
bit; its trajectories are NumPy arrays over the result's own memory."""

import gc
import json

import numpy as np
import pytest

import emrm
from conftest import SOURCE_DIR, run_emrm

# One cell of each region (the green one is bench_simulate's BM_CellGreen), an infeasible one, and
# one with every factor and the seed away from their defaults.
CELLS = [
    dict(speed_kph=50, ttc_s=1.2),
    dict(speed_kph=60, ttc_s=0.8),
    dict(speed_kph=72, ttc_s=0.3),
    dict(speed_kph=72, ttc_s=2.9),
    dict(speed_kph=55, ttc_s=0.9, mu=0.8, passage_m=2.5, truck_speed_kph=15, seed=7),
]
FLAGS = {"speed_kph": "--speed-kph", "ttc_s": "--ttc-s", "mu": "--mu", "passage_m": "--passage-m",
         "truck_speed_kph": "--truck-speed-kph", "seed": "--seed"}


def without_scene(printed):
    """The CLI's JSON without the "scene" it adds (the file, profile and actuation it was told)."""
    parsed = json.loads(printed)
    assert "actuation" in parsed.pop("scene")
    return parsed


def cli_json(cell, *more):
    args = ["simulate", "--json", *more]
    for key, value in cell.items():
        args += [FLAGS[key], repr(value)]
    run = run_emrm(*args)
    assert run.returncode == 0, run.stderr
    return run.stdout


def assert_same_fields(result, printed):
    """Every key of the CLI's JSON is an attribute of the result with the same value."""
    for key, value in printed.items():
        if key != "strategies":
            assert getattr(result, key) == value, key
    assert sorted(result.strategies) == sorted(printed["strategies"])  # JSON sorts them; Python keeps evaluation order
    for name, fields in printed["strategies"].items():
        outcome = result.strategies[name]
        for key, value in fields.items():
            if key in ("trajectory", "truck_trajectory"):
                trajectory = getattr(outcome, key)
                assert len(trajectory) == len(value)
                for column in value[0] if value else []:
                    assert np.array_equal(trajectory[column], [p[column] for p in value]), (name, key, column)
            else:
                assert getattr(outcome, key) == value, (name, key)


@pytest.mark.parametrize("cell", CELLS, ids=lambda c: "_".join(f"{k}{v}" for k, v in c.items()))
def test_simulate_prints_what_the_cli_prints(cell):
    printed = without_scene(cli_json(cell))
    result = emrm.simulate(**cell)
    assert json.loads(result.to_json()) == printed  # every number as the CLI prints it
    assert_same_fields(result, printed)


def test_a_scene_file_a_profile_and_some_strategies_as_the_cli_takes_them(examples):
    cell = dict(speed_kph=55, ttc_s=1.0, mu=0.8)
    printed = cli_json(cell, "--scene", examples / "scene.yaml", "--profile", "paper", "--strategy", "dodge",
                       "--strategy", "emrm")
    scene = emrm.Scene.load(examples / "scene.yaml", profile="paper")
    result = emrm.simulate(scene, strategy=["dodge", "emrm"], **cell)
    assert json.loads(result.to_json()) == without_scene(printed)
    assert_same_fields(result, without_scene(printed))
    assert list(result.strategies) == ["dodge", "emrm"]


def test_a_scene_reads_back_from_its_dict_and_its_pickle(examples):
    import pickle

    scene = emrm.Scene.load(examples / "scene.yaml", profile="paper")
    assert emrm.Scene.from_dict(scene.to_dict()) == scene
    assert pickle.loads(pickle.dumps(scene)) == scene
    assert scene != emrm.Scene()


def test_trajectories_are_views_of_the_result_without_copies():
    result = emrm.simulate(speed_kph=60, ttc_s=0.8)
    trajectory = result.strategies["dodge"].trajectory
    for column in ("t", "x", "y", "psi", "v", "vx", "vy", "yaw_rate", "steer"):
        first, second = trajectory[column], getattr(trajectory, column)
        assert first.base is not None and not first.flags.owndata, column
        assert not first.flags.writeable, column
        assert first.__array_interface__["data"][0] == second.__array_interface__["data"][0], column
    # x, y, psi, t lie in the simulator's array of samples: one stride apart, no gather.
    x, y = trajectory.x, trajectory.y
    assert x.strides == y.strides and x.strides[0] > x.itemsize
    assert y.__array_interface__["data"][0] - x.__array_interface__["data"][0] == x.itemsize
    truck = result.strategies["dodge"].truck_trajectory
    assert truck.t.__array_interface__["data"][0] == trajectory.t.__array_interface__["data"][0]
    assert truck.columns == ("t", "x", "y", "psi")
    with pytest.raises(AttributeError):
        truck.vx


def test_an_array_keeps_its_result_alive():
    x = emrm.simulate(speed_kph=60, ttc_s=0.8).strategies["dodge"].trajectory.x
    copy = x.copy()
    gc.collect()
    emrm.simulate(speed_kph=72, ttc_s=0.3)  # reuses freed memory, if any was freed
    assert np.array_equal(x, copy)


def test_keys_the_json_leaves_out_read_none():
    infeasible = emrm.simulate(speed_kph=72, ttc_s=2.9)
    assert not infeasible.feasible and infeasible.strategies == {}
    assert infeasible.evidence is None and infeasible.certificate is None
    stop = emrm.simulate(speed_kph=50, ttc_s=1.2).strategies["emergency_stop"]
    assert stop.chosen_strategy is None and stop.loss_evaluation_trace is None
    with pytest.raises(AttributeError):
        infeasible.no_such_key


def test_bad_cells_raise_what_the_cli_prints():
    run = run_emrm("simulate", "--speed-kph=-5", "--ttc-s", "1")
    assert run.returncode == 2
    with pytest.raises(emrm.UsageError) as error:
        emrm.simulate(speed_kph=-5, ttc_s=1)
    assert str(error.value) == run.stderr.strip().removeprefix("error: ")  # the CLI says "error:" first
    assert isinstance(error.value, ValueError)
    run = run_emrm("simulate", "--speed-kph", "50", "--ttc-s", "1", "--strategy", "fly")
    with pytest.raises(emrm.UsageError) as error:
        emrm.simulate(speed_kph=50, ttc_s=1, strategy="fly")
    assert str(error.value) == run.stderr.strip().removeprefix("error: ")  # the CLI says "error:" first
    with pytest.raises(TypeError):
        emrm.simulate(speed_kph="fast", ttc_s=1)


def test_the_factors_are_the_scenes_keywords():
    # Every factor of the scene's table is a keyword and reaches the cell as `emrm simulate --KEY`.
    given = {"speed_kph": 40, "ttc_s": 1.5, "mu": 0.7, "passage_m": 2.5, "truck_speed_kph": 0}
    cell = emrm.simulate(**given, strategy="emergency_stop", certify=False)
    flags = [f"--{key.replace('_', '-')}={value}" for key, value in given.items()]
    run = run_emrm("simulate", *flags, "--strategy", "emergency_stop", "--no-certify", "--json")
    assert run.returncode == 0, run.stderr
    assert cell.to_dict()["input"] == json.loads(run.stdout)["input"]
    assert cell.to_dict()["input"] == {**given, "seed": 1}
    # Left out, a factor is the scene's default; a key the scene has no factor for is refused,
    # naming the factors; the ego speed and the TTC are required.
    assert emrm.simulate(speed_kph=40, ttc_s=1.5, strategy="emergency_stop").to_dict()["input"]["mu"] == 1
    with pytest.raises(emrm.UsageError, match="no factor 'friction'.*speed_kph, ttc_s, mu, passage_m, truck_speed_kph"):
        emrm.simulate(speed_kph=40, ttc_s=1.5, friction=0.5)
    with pytest.raises(emrm.UsageError, match="ttc_s is required"):
        emrm.simulate(speed_kph=40)


def test_a_bad_scene_file_raises_input_error_at_its_line_and_column(tmp_path, examples):
    text = (examples / "scene.yaml").read_text().replace("lane_width_m: 3.5", "lane_width_m: -1")
    scene_file = tmp_path / "scene.yaml"
    scene_file.write_text(text)
    run = run_emrm("simulate", "--scene", scene_file, "--speed-kph", "50", "--ttc-s", "1")
    assert run.returncode == 2
    with pytest.raises(emrm.InputError) as error:
        emrm.simulate(scene_file, speed_kph=50, ttc_s=1)
    assert str(error.value) == run.stderr.strip().removeprefix("error: ")  # the CLI says "error:" first
    line = next(n for n, t in enumerate(text.splitlines(), 1) if "lane_width_m: -1" in t)
    assert (error.value.file, error.value.line) == (str(scene_file), line)
    assert error.value.column == text.splitlines()[line - 1].index("-1") + 1
    with pytest.raises(emrm.InputError):
        emrm.Scene.load(scene_file)


def test_other_threads_run_while_a_cell_simulates():
    """The GIL is released inside simulate: a Python thread counts on meanwhile."""
    import threading

    counting = threading.Event()
    done = threading.Event()
    count = 0

    def count_while_simulating():
        nonlocal count
        counting.set()
        while not done.is_set():
            count += 1

    counter = threading.Thread(target=count_while_simulating)
    counter.start()
    counting.wait()
    before = count
    emrm.simulate(speed_kph=72, ttc_s=0.3, certify=False)  # every search in full: a long call
    during = count - before
    done.set()
    counter.join()
    assert during > 1000


def test_threads_simulating_side_by_side_give_the_sequential_results():
    from concurrent.futures import ThreadPoolExecutor

    sequential = [emrm.simulate(**cell).to_json() for cell in CELLS]
    with ThreadPoolExecutor(max_workers=4) as pool:
        parallel = list(pool.map(lambda cell: emrm.simulate(**cell).to_json(), CELLS * 2))
    assert parallel == sequential * 2


def test_another_family_takes_its_factors_and_its_levels_by_name():
    # The highway of the paper's introduction: a categorical factor by its level's name, as
    # `emrm simulate --factor obstacle=deer` takes it; the result is the CLI's, number for number.
    scene = emrm.Scene.load(SOURCE_DIR / "examples" / "highway_obstacle" / "scene.yaml")
    assert scene.family == "highway_obstacle" and scene.highway.deer.mass_kg == 70
    cell = emrm.simulate(scene, speed_kph=100, ttc_s=1.2, obstacle="deer", blocked_m=5)
    run = run_emrm("simulate", "--scene", SOURCE_DIR / "examples" / "highway_obstacle" / "scene.yaml",
                   "--speed-kph", "100", "--ttc-s", "1.2", "--factor", "obstacle=deer", "--factor", "blocked_m=5",
                   "--json")
    assert run.returncode == 0, run.stderr
    assert json.loads(cell.to_json()) == without_scene(run.stdout)
    assert cell.input["obstacle"] == 1 and cell.actors[0]["kind"] == "animal"
    assert emrm.simulate(scene, speed_kph=100, ttc_s=1.2, obstacle=1, blocked_m=5).to_json() == cell.to_json()
    with pytest.raises(emrm.UsageError, match="obstacle is one of truck, deer, got 'moose'"):
        emrm.simulate(scene, speed_kph=100, ttc_s=1.2, obstacle="moose")
    with pytest.raises(TypeError, match="blocked_m must be a number, not str"):
        emrm.simulate(scene, speed_kph=100, ttc_s=1.2, blocked_m="wide")
    # A pedestrian stepping out from behind a parked car, an oncoming car in the other lane.
    street = emrm.Scene.load(SOURCE_DIR / "examples" / "pedestrian_crossing" / "scene.yaml")
    assert isinstance(street.crossing, emrm.CrossingConfig) and street.crossing.pedestrian.mass_kg == 75
    met = emrm.simulate(street, speed_kph=40, ttc_s=0.9, oncoming="car")
    assert [a["name"] for a in met.actors] == ["pedestrian", "parked car", "oncoming car"]
    assert met.unmitigated["loss_level"] == 7
    # A car cutting in 30 km/h slower and braking, a car overtaking in the left lane.
    motorway = emrm.Scene.load(SOURCE_DIR / "examples" / "cut_in" / "scene.yaml")
    assert isinstance(motorway.cut_in, emrm.CutInConfig) and motorway.cut_in.cutting.mass_kg == 1500
    cut = emrm.simulate(motorway, speed_kph=100, ttc_s=1.0, relative_speed_kph=30, following="car")
    assert [a["name"] for a in cut.actors] == ["cutting car", "following car"]


def test_every_function_and_method_has_a_signature_ides_and_jupyter_read():
    """Issue 40, 13: inspect.signature(emrm.simulate) raised (the extension's builtins carry none)."""
    import inspect

    unreadable = []
    for name in emrm.__all__:
        value = getattr(emrm, name)
        members = [(name, value)]
        if isinstance(value, type) and not issubclass(value, BaseException):
            members += [(f"{name}.{m}", getattr(value, m)) for m in vars(value) if not m.startswith("_")]
        for label, member in members:
            if callable(member) and not isinstance(member, type):
                try:
                    inspect.signature(member)
                except (TypeError, ValueError):
                    unreadable.append(label)
    assert unreadable == []
    # The signature is the C++ argument list's, defaults included, and it is what the call takes.
    simulate = inspect.signature(emrm.simulate).parameters
    assert {k: p.default for k, p in simulate.items() if p.default is not inspect.Parameter.empty} == {
        "scene": None, "strategy": None, "seed": 1, "certify": True, "timing": False}
    assert simulate["strategy"].kind is inspect.Parameter.KEYWORD_ONLY
    assert inspect.signature(emrm.check_fsm).parameters["max_states"].default == 100000
    assert list(inspect.signature(emrm.Scene.load).parameters) == ["path", "profile"]
    with pytest.raises(TypeError):
        emrm.simulate(None, "dodge", speed_kph=50, ttc_s=1)  # strategy is keyword-only, as the signature says
    assert emrm.simulate.__doc__ == emrm._emrm.simulate.__doc__
