"""Covering arrays and the minimum scenario set from Python are `emrm ca`'s and `emrm plan`'s."""

import csv
import io
import shutil

import numpy as np
import pandas
import pytest

import emrm
from conftest import run_emrm


def cli_rows(*args):
    run = run_emrm("ca", *args)
    assert run.returncode == 0, run.stderr
    return run.stdout


def test_covering_array_is_emrm_ca_levels():
    printed = cli_rows("--levels", "3,3,2,4", "--strength", "3", "--seed", "7")
    array = emrm.covering_array([3, 3, 2, 4], 3, seed=7)
    assert isinstance(array, np.ndarray) and array.shape[1] == 4
    assert np.array_equal(array, np.loadtxt(io.StringIO(printed), delimiter=",", skiprows=1, dtype=int))
    assert emrm.check_covering_array([3, 3, 2, 4], 3, array)["ok"]


def test_constraints_are_pict_over_p1_p2_or_a_function(tmp_path):
    constraint = "IF [p1] = 0 THEN [p2] <> 2;"
    model = tmp_path / "model.txt"
    model.write_text("p1: 0, 1, 2\np2: 0, 1, 2\np3: 0, 1\n" + constraint + "\n")
    array = emrm.covering_array([3, 3, 2], constraints=constraint)
    assert np.array_equal(array, np.loadtxt(io.StringIO(cli_rows(model)), delimiter=",", skiprows=1, dtype=int))
    assert not any(row[0] == 0 and row[1] == 2 for row in array)

    def breaks(row):  # the same constraint; -1 is a level not chosen yet
        return row[0] == 0 and row[1] == 2

    by_function = emrm.covering_array([3, 3, 2], constraints=breaks)
    assert emrm.check_covering_array([3, 3, 2], 2, by_function, constraint)["ok"]
    assert not emrm.check_covering_array([3, 3, 2], 2, [[0, 2, 0]] + array.tolist(), constraint)["ok"]


def test_errors_in_constraints_point_into_the_constraints():
    with pytest.raises(emrm.InputError) as error:
        emrm.covering_array([2, 2], constraints="[p1] = 0;\nIF [p9] = 1 THEN [p2] = 0;")
    assert error.value.file == "<constraints>" and error.value.line == 2
    with pytest.raises(emrm.UsageError):
        emrm.covering_array([2, 2], 4)
    with pytest.raises(ValueError):
        emrm.covering_array([2, 0, 2])
    with pytest.raises(ZeroDivisionError):  # a function's own exception comes through as it is
        emrm.covering_array([2, 2], constraints=lambda row: 1 / 0)


def test_a_model_file_gives_its_values_as_emrm_ca_prints_them(tmp_path):
    model = tmp_path / "model.txt"
    model.write_text('Speed: 30, 50, 70\nRoad: dry, wet, icy\nIF [Road] = "icy" THEN [Speed] <= 50;\n')
    frame = emrm.covering_array_model(model)
    pandas.testing.assert_frame_equal(frame, pandas.read_csv(io.StringIO(cli_rows(model))))
    assert frame.Speed.dtype.kind == "i" and frame.Road.dtype == object


def test_plan_is_emrm_plan(tmp_path, examples):
    run = run_emrm("plan", examples / "odd.yaml", "-o", tmp_path / "cli")
    assert run.returncode == 0, run.stderr
    planned = emrm.plan(examples / "odd.yaml", out_dir=tmp_path / "python")
    for name in ("scenarios.csv", "scenarios.json", "coverage.json", "coverage.csv", "coverage.md"):
        assert (tmp_path / "python" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    with open(tmp_path / "cli" / "scenarios.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(planned.scenarios) == len(rows)
    for i, row in enumerate(rows):
        for column, text in row.items():
            value = planned.scenarios[column].iloc[i]
            assert (format(value, ".9g") if isinstance(value, float) else str(value)) == text, (i, column)
    assert planned.satisfied and planned.analysis is not None and planned.analysis.errors == 0
    assert list(planned.coverage.columns)[1:] == [r["name"] for r in
                                                  [planned.coverage_json["plan"], *planned.coverage_json["baselines"]]]


def test_plan_refuses_a_safety_case_with_error_findings(tmp_path, examples):
    for name in ("odd.yaml", "safety.yaml", "scene.yaml", "emrm_fsm.yaml"):
        shutil.copy(examples / name, tmp_path / name)
    safety = tmp_path / "safety.yaml"
    safety.write_text(safety.read_text().replace("hazards: [H2, H6]", "hazards: [H2, H42]"))
    assert run_emrm("plan", tmp_path / "odd.yaml", "-o", tmp_path / "cli").returncode == 1
    with pytest.raises(emrm.FindingsError) as error:
        emrm.plan(tmp_path / "odd.yaml")
    assert "SAF001" in set(error.value.analysis.findings.code)
    assert len(emrm.plan(tmp_path / "odd.yaml", allow_findings=True).scenarios) > 0


def test_a_bad_odd_raises_input_error(tmp_path, examples):
    odd = tmp_path / "odd.yaml"
    odd.write_text((examples / "odd.yaml").read_text().replace("strength: 2", "strength: 7"))
    run = run_emrm("plan", odd, "-o", tmp_path / "out")
    assert run.returncode == 2
    with pytest.raises(emrm.InputError) as error:
        emrm.plan(odd)
    assert str(error.value) == run.stderr.strip().removeprefix("error: ")  # the CLI says "error:" first
    with pytest.raises(emrm.InputError) as error:
        emrm.plan({"name": "empty"})
    assert error.value.file == "<odd mapping>"
