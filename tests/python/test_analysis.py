"""The safety-case analysis and the FSM checks from Python are `emrm analyze`'s and `emrm fsm`'s."""

import csv
import json

import pytest

import emrm
from conftest import run_emrm


def test_analyze_is_emrm_analyze(tmp_path, examples):
    run = run_emrm("analyze", examples / "safety.yaml", "--format", "json", "-o", tmp_path / "cli")
    assert run.returncode == 0, run.stderr
    analysis = emrm.analyze(examples / "safety.yaml")
    assert analysis.to_dict() == json.loads(run.stdout)
    assert analysis.to_text() == run_emrm("analyze", examples / "safety.yaml").stdout
    written = analysis.write(tmp_path / "python")
    assert [p.name for p in written] == ["traceability.csv", "traceability.md", "findings.json", "asil.csv"]
    for path in written:
        assert path.read_bytes() == (tmp_path / "cli" / path.name).read_bytes(), path.name
    with open(tmp_path / "cli" / "traceability.csv", newline="") as f:
        assert analysis.traceability.to_dict("records") == list(csv.DictReader(f))
    with open(tmp_path / "cli" / "asil.csv", newline="") as f:
        assert analysis.asil.to_dict("records") == list(csv.DictReader(f))
    assert analysis.findings.to_dict("records") == json.loads(run.stdout)["findings"]


def test_findings_are_rows_and_a_malformed_case_raises(tmp_path, examples):
    safety = tmp_path / "safety.yaml"
    safety.write_text((examples / "safety.yaml").read_text().replace("hazards: [H2, H6]", "hazards: [H2, H42]"))
    analysis = emrm.analyze(safety, no_fsm=True)
    assert analysis.errors == 1
    errors = analysis.findings[analysis.findings.severity == "error"]
    assert errors.code.tolist() == ["SAF001"] and "'H42'" in errors.message.iloc[0]
    safety.write_text("name: [broken\n")
    run = run_emrm("analyze", safety)
    assert run.returncode == 2
    with pytest.raises(emrm.InputError) as error:
        emrm.analyze(safety)
    assert str(error.value) == run.stderr.strip().removeprefix("error: ")  # the CLI says "error:" first
    with pytest.raises(emrm.InputError) as error:
        emrm.analyze(tmp_path / "missing.yaml")
    assert error.value.file == str(tmp_path / "missing.yaml") and error.value.line is None


def test_check_fsm_is_emrm_fsm(examples):
    fsm = examples / "emrm_fsm.yaml"
    run = run_emrm("fsm", fsm, "--check", "--words", "3", "--word", "hazard_detected high_risk", "--format", "json")
    assert run.returncode == 0, run.stderr
    report = emrm.check_fsm(fsm, words=3, word=["hazard_detected high_risk"])
    assert report.ok and report.to_dict() == json.loads(run.stdout)
    composed = emrm.check_fsm(fsm, compose=examples / "loss_evaluation_fsm.yaml")
    run = run_emrm("fsm", fsm, "--check", "--compose", examples / "loss_evaluation_fsm.yaml")
    assert composed.to_text() == run.stdout and composed.ok == (run.returncode == 0)
    assert composed.dot().startswith("digraph")
