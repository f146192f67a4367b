"""emrm.sweep writes what `emrm sweep` writes; load_results gives the numbers of cells.csv and
regions.csv at full precision; the results do not depend on the thread count; Ctrl-C stops a sweep
that a second call resumes with no cell lost or stored twice."""

import csv
import json
import math
import os
import signal
import subprocess
import sys
import time

import numpy
import pandas
import pytest

import emrm
from conftest import run_emrm

# 16 cells over both regions a stop decides, some infeasible; a second grid lists its cells.
CAMPAIGN = """seed: 5
grids:
  - name: map
    speed_kph: {from: 30, to: 72, step: 14}
    ttc_s: {from: 0.25, to: 1.45, step: 0.4}
  - name: slippery
    ttc_s: 0.9
    cells:
      - {speed_kph: 40, mu: 0.3}
      - {speed_kph: 55, mu: 0.6, passage_m: 1.5, truck_speed_kph: 20}
"""


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    """The campaign swept by the CLI, and by Python with one and with two threads."""
    folder = tmp_path_factory.mktemp("sweep")
    campaign = folder / "campaign.yaml"
    campaign.write_text(CAMPAIGN)
    run = run_emrm("sweep", campaign, "-o", folder / "cli", "--threads", "2")
    assert run.returncode == 0, run.stderr
    one = emrm.sweep(campaign, folder / "one", threads=1)
    two = emrm.sweep(campaign, folder / "two", threads=2)
    return folder, one, two


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def as_csv(value):
    """A value as the exports write it: numbers with {:.6g}, flags 1/0, NaN blank."""
    if isinstance(value, (bool, numpy.bool_)):
        return "1" if value else "0"
    if isinstance(value, float):
        return "" if math.isnan(value) else format(value, ".6g")
    return str(value)


def assert_frame_is_csv(frame, rows):
    assert len(frame) == len(rows)
    columns = list(rows[0]) if rows else []
    assert [c for c in frame.columns if c in columns] == columns  # in the file's order
    for i, row in enumerate(rows):
        for column, text in row.items():
            assert as_csv(frame[column].iloc[i]) == text, (i, column)


def test_python_writes_the_files_the_cli_writes(swept):
    folder, one, _ = swept
    for name in ("regions.csv", "cells.csv", "cells.json"):
        assert (folder / "one" / name).read_bytes() == (folder / "cli" / name).read_bytes(), name
    assert one.summary["cells_total"] == 18 and one.summary["cells_simulated"] == 18


def test_load_results_has_the_numbers_of_the_csv_files(swept):
    folder, _, _ = swept
    results = emrm.load_results(folder / "cli")
    assert_frame_is_csv(results["cells"], read_csv(folder / "cli" / "cells.csv"))
    assert_frame_is_csv(results["regions"], read_csv(folder / "cli" / "regions.csv"))
    assert results.meta["grids"] == ["map", "slippery"] and results.meta["seed"] == 5


def test_the_columns_after_the_csv_files_hold_the_rest_of_cells_json(swept):
    folder, _, _ = swept
    results = emrm.load_results(folder / "cli")
    regions, cells = results.regions, results.cells
    for column in ("seed", "strengthened", "certificate", "inferred_from", "unmitigated_p_fatal"):
        assert column in regions.columns, column
    for column in ("contact", "p_fatal", "fsm_trace", "chosen_strategy", "maneuver", "seed"):
        assert column in cells.columns, column
    documents = json.loads((folder / "cli" / "cells.json").read_text())
    assert len(documents) == len(regions)
    outcome_row = 0
    for i, cell in enumerate(documents):
        row = regions.iloc[i]
        assert (row.grid, row["index"], row.seed) == (cell["grid"], cell["index"], cell["seed"])
        if "certificate" in cell:
            assert json.loads(row.certificate) == cell["certificate"]
        if "unmitigated" in cell:
            assert row.unmitigated_p_fatal == cell["unmitigated"]["p_fatal"]
            assert bool(row.strengthened) == cell["strengthened"]
        for outcome in cell.get("outcomes", []):
            mine = cells.iloc[outcome_row]
            assert mine.strategy == outcome["strategy"] and bool(mine.contact) == outcome["contact"]
            assert mine.fsm_trace == " ".join(outcome["fsm_trace"]) and mine.seed == cell["seed"]
            assert mine.chosen_strategy == outcome["chosen_strategy"] and mine.maneuver.startswith("{")
            outcome_row += 1
    assert outcome_row == len(cells)


def test_kpis_count_the_cells_table(swept):
    _, one, _ = swept
    cells, kpis = one.cells, one.kpis
    whole = kpis[kpis.factor == "all"]
    for row in whole.itertuples():
        mine = cells[(cells.grid == row.grid) & (cells.strategy == row.strategy)]
        assert row.cells == len(mine) and row.avoided == mine.avoided.sum()
        assert row.collision_avoidance_rate_pct == pytest.approx(100 * mine.avoided.mean())


def test_results_do_not_depend_on_the_thread_count(swept):
    _, one, two = swept
    for table in ("cells", "regions", "kpis"):
        pandas.testing.assert_frame_equal(one[table], two[table])


def test_a_second_sweep_into_the_folder_finds_everything_stored(swept):
    folder, _, _ = swept
    again = emrm.sweep(folder / "campaign.yaml", folder / "one", threads=1)
    assert again.summary["cells_done_before"] == 18 and again.summary["cells_simulated"] == 0


def test_a_mapping_stands_for_a_campaign_file_and_a_temporary_folder_for_out_dir(swept):
    _, one, _ = swept
    grid = {"name": "map", "speed_kph": {"from": 30, "to": 72, "step": 14}, "ttc_s": {"from": 0.25, "to": 1.45, "step": 0.4}}
    results = emrm.sweep({"seed": 5, "grids": [grid]}, threads=2)
    assert results.dir is None
    pandas.testing.assert_frame_equal(results.regions, one.regions[one.regions.grid == "map"])


def test_bad_campaigns_raise_input_error_with_the_cli_message(tmp_path):
    campaign = tmp_path / "campaign.yaml"
    campaign.write_text("grids:\n  - name: g\n    mu: 3\n")
    run = run_emrm("sweep", campaign, "-o", tmp_path / "out")
    assert run.returncode == 2
    with pytest.raises(emrm.InputError) as error:
        emrm.sweep(campaign, tmp_path / "out")
    assert str(error.value) == run.stderr.strip().removeprefix("error: ")  # the CLI says "error:" first
    assert error.value.line == 3
    with pytest.raises(emrm.InputError) as error:
        emrm.sweep({"grids": [{"name": "g", "mu": 3}]})
    assert error.value.file == "<campaign mapping>"
    with pytest.raises(emrm.UsageError):
        emrm.load_results(tmp_path / "nothing here")


# 5 speeds x 12 TTCs x 2 frictions, 86 feasible cells: each option of the search but --spread
# changes what it simulates here.
ADAPTIVE_CAMPAIGN = """seed: 2
grids:
  - name: map
    speed_kph: {from: 30, to: 70, step: 10}
    ttc_s: {from: 0.25, to: 2.45, levels: 12}
    mu: [0.4, 1.0]
    passage_m: 3.0
"""


@pytest.fixture(scope="module")
def adaptive_campaign(tmp_path_factory):
    folder = tmp_path_factory.mktemp("adaptive")
    campaign = folder / "campaign.yaml"
    campaign.write_text(ADAPTIVE_CAMPAIGN)
    return campaign


def adaptive_summary(campaign, out, flags, **keywords):
    """The grid's adaptive summary swept by Python with `keywords`, checked against `emrm sweep
    --adaptive FLAGS` into a folder beside it: each keyword is the option it names."""
    by_python = emrm.sweep(campaign, out, threads=2, progress=False, adaptive=True, **keywords).summary["adaptive"]
    run = run_emrm("sweep", campaign, "-o", f"{out}-cli", "--threads", "2", "--adaptive", *flags)
    assert run.returncode == 0, run.stderr
    assert by_python == list(emrm.load_results(f"{out}-cli").adaptive.values())
    assert len(by_python) == 1
    return by_python[0]


def test_sweep_takes_every_option_of_the_adaptive_search(adaptive_campaign, tmp_path):
    # None is the command's default for each.
    defaults = adaptive_summary(adaptive_campaign, tmp_path / "defaults", [], verify_sample=None, stride=None,
                                brackets=None, spread=None, initial_levels=None)
    base = adaptive_summary(adaptive_campaign, tmp_path / "base", ["--verify-sample", "0"], verify_sample=0)
    assert defaults["verification"]["sampled"] > 0 and base["verification"]["sampled"] == 0

    def without_sample(name, flags, **keywords):
        return adaptive_summary(adaptive_campaign, tmp_path / name, ["--verify-sample", "0", *flags], verify_sample=0,
                                **keywords)

    # Each keyword reaches the search as its option does, and changes what it simulates.
    stride = without_sample("stride", ["--stride", "1"], stride=1)
    assert stride["simulated_cells"] > base["simulated_cells"]
    levels = without_sample("levels", ["--initial-levels", "5"], initial_levels=5)
    assert levels["simulated_cells"] > base["simulated_cells"]
    searched = without_sample("search", ["--brackets", "search"], brackets="search")
    assert searched["simulated_for"]["threshold_brackets"] > base["simulated_for"]["threshold_brackets"]
    without_sample("spread", ["--spread", "1"], spread=1)


def test_bad_adaptive_options_are_refused_before_the_sweep_starts(adaptive_campaign, tmp_path):
    for keywords in ({"stride": 0}, {"spread": 0}, {"initial_levels": 1}, {"brackets": "exact"}):
        out = tmp_path / "-".join(keywords)
        with pytest.raises(ValueError):
            emrm.sweep(adaptive_campaign, out, threads=1, progress=False, adaptive=True, **keywords)
        assert not (out / "results.sqlite").exists(), keywords
    with pytest.raises(emrm.UsageError, match="brackets: expected one of auto, search, predict, got 'exact'"):
        emrm.sweep(adaptive_campaign, tmp_path / "exact", adaptive=True, brackets="exact")


# 88 cells, four seconds on one thread: long enough to be interrupted after the first.
LONG_CAMPAIGN = """seed: 5
grids:
  - name: map
    speed_kph: {from: 30, to: 72, step: 6}
    ttc_s: {from: 0.45, to: 1.45, step: 0.1}
"""

SWEEP_SCRIPT = """
import sys, emrm
print("sweeping", flush=True)
emrm.sweep(sys.argv[1], sys.argv[2], threads=1)
"""


def test_ctrl_c_stops_a_sweep_that_the_next_call_resumes(tmp_path):
    campaign = tmp_path / "campaign.yaml"
    campaign.write_text(LONG_CAMPAIGN)
    out = tmp_path / "out"
    child = subprocess.Popen([sys.executable, "-c", SWEEP_SCRIPT, campaign, out], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, env=os.environ)
    assert child.stdout.readline().strip() == "sweeping"
    for _ in range(600):
        if (out / "results.sqlite").exists():
            break
        time.sleep(0.05)
    time.sleep(0.5)
    child.send_signal(signal.SIGINT)
    _, err = child.communicate(timeout=120)
    if child.returncode == 0:
        pytest.skip("the sweep ended before the interrupt")
    assert "emrm.Interrupted: interrupted: " in err and "cells stored in" in err, err
    stored = int(err.split("interrupted: ")[1].split(" of ")[0])
    assert 0 <= stored < 88  # none yet stored on a machine slowed right down: the rerun does them all

    resumed = emrm.sweep(campaign, out, threads=2)
    assert resumed.summary["cells_done_before"] == stored
    assert resumed.summary["cells_simulated"] == 88 - stored
    fresh = emrm.sweep(campaign, tmp_path / "fresh", threads=2)
    for name in ("regions.csv", "cells.csv"):  # none lost, none twice
        assert (out / name).read_bytes() == (tmp_path / "fresh" / name).read_bytes()
    pandas.testing.assert_frame_equal(resumed.cells, fresh.cells)


def test_the_example_draws_the_map_of_a_results_folder(tmp_path):
    """examples/notebooks/mitigability_map.py on a small grid named as the shipped fine grid."""
    from conftest import SOURCE_DIR

    campaign = tmp_path / "campaign.yaml"
    campaign.write_text("grids:\n  - name: fine\n    speed_kph: [30, 50, 70]\n    ttc_s: [0.3, 0.9, 1.5, 2.9]\n")
    emrm.sweep(campaign, tmp_path / "out", threads=2)
    example = SOURCE_DIR / "examples" / "notebooks" / "mitigability_map.py"
    run = subprocess.run([sys.executable, example, "--results", tmp_path / "out"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert "regions: G " in run.stdout
    # scripts/install-deps.sh installs matplotlib (python3-matplotlib): the example draws the map.
    assert (tmp_path / "out" / "mitigability_map.png").exists(), run.stdout
