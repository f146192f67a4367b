"""emrm.Scene: every field of scene.yaml as a read-only attribute, copies with changes, checked as
a scene file is; and the stubs (python/emrm/_emrm.pyi) name exactly what the module has."""

import ast
from pathlib import Path

import pytest

import emrm
from emrm import _emrm

STUBS = Path(_emrm.__file__).with_name("_emrm.pyi")


def test_attributes_are_the_yaml_fields(examples):
    scene = emrm.Scene.load(examples / "scene.yaml")
    fields = scene.to_dict()
    assert list(fields)[:4] == ["name", "family", "road", "truck"]
    for key, value in fields.items():
        attribute = getattr(scene, key)
        assert (attribute.to_dict() if isinstance(value, dict) else attribute) == value
    assert scene.truck.speed_kph == 10.0 and scene.road.lanes == 2
    with pytest.raises(AttributeError):
        scene.truck.speed_kph = 20


def test_with_changes_a_copy_in_three_spellings():
    scene = emrm.Scene()
    for faster in (scene.with_(truck={"speed_kph": 20}), scene.with_(truck__speed_kph=20),
                   scene.with_({"truck.speed_kph": 20})):
        assert faster.truck.speed_kph == 20 and faster.truck.length_m == scene.truck.length_m
        assert faster.road == scene.road
    assert scene.truck.speed_kph == 10
    assert scene.with_(name="other", max_initial_distance_m=30).max_initial_distance_m == 30
    assert emrm.simulate(scene.with_(truck__speed_kph=20), speed_kph=50, ttc_s=1).input["truck_speed_kph"] == 20


def test_changes_are_checked_as_a_scene_file_is():
    with pytest.raises(emrm.InputError) as error:
        emrm.Scene().with_(road__lane_width_m=-1)
    assert "road.lane_width_m: expected a value > 0, got -1" in str(error.value)
    with pytest.raises(emrm.InputError) as error:
        emrm.Scene.from_dict({"truck": {"sped_kph": 20}})
    assert "sped_kph" in str(error.value) and error.value.file == "<scene mapping>"
    with pytest.raises(emrm.InputError):
        emrm.Scene().with_(road={"lanes": "two"})


def test_the_yaml_reads_back(tmp_path, examples):
    scene = emrm.Scene.load(examples / "scene.yaml", profile="production")
    (tmp_path / "scene.yaml").write_text(scene.to_yaml())
    assert emrm.Scene.load(tmp_path / "scene.yaml") == scene


def test_an_imported_scenario_is_a_scene(examples):
    # The .xosc itself and the scene file made of it, as every command takes them (docs/import.md).
    folder = examples.parent / "openscenario"
    direct = emrm.Scene.load(folder / "cut_in.xosc")
    assert direct.family == "openscenario" and direct.openscenario.speed_parameter == "EgoSpeed"
    assert [f.parameter for f in direct.openscenario.factors] == ["RelativeSpeed", "LaneChangeTime", "CutInGap",
                                                                  "TargetDecel"]
    scene = emrm.Scene.load(folder / "scene.yaml")
    assert scene.openscenario.factors[1].unit == "s" and scene.openscenario.factors[1].min == 0.5
    result = emrm.simulate(scene, speed_kph=100, ttc_s=0.5, RelativeSpeed=11.11)
    assert result.input["RelativeSpeed"] == 11.11 and result.input["LaneChangeTime"] == 2.0
    with pytest.raises(emrm.InputError) as error:
        emrm.Scene.from_dict({"family": "openscenario", "openscenario": {"file": str(folder / "cut_in.xosc"),
                                                                         "onset_search_s": -1}})
    assert "onset_search_s" in str(error.value)


def stub_tree():
    return ast.parse(STUBS.read_text())


def stub_classes():
    return {node.name: node for node in stub_tree().body if isinstance(node, ast.ClassDef)}


def members(node):
    """The attributes a stub class declares (`name: type`, or `name: Final[type]` when read-only), with their types."""
    types = {}
    for item in node.body:
        if isinstance(item, ast.AnnAssign):
            annotation = item.annotation
            if isinstance(annotation, ast.Subscript) and ast.unparse(annotation.value) == "Final":
                annotation = annotation.slice
            types[item.target.id] = ast.unparse(annotation)
    return types


def test_the_stubs_name_what_the_module_has():
    declared = {node.name for node in stub_tree().body if isinstance(node, (ast.ClassDef, ast.FunctionDef))}
    declared |= {node.target.id for node in stub_tree().body if isinstance(node, ast.AnnAssign)}
    present = {name for name in dir(_emrm) if not name.startswith("__")} | {"__version__"}
    assert present <= declared
    assert {name for name in declared - present if not name.startswith("_")} == set()


def test_the_stubs_list_every_scene_field_with_its_type():
    classes = stub_classes()
    scene = emrm.Scene()
    parts = {"Scene": scene} | {type(getattr(scene, k)).__name__: getattr(scene, k)
                                for k, v in scene.to_dict().items() if isinstance(v, dict)}
    for name, part in parts.items():
        declared = members(classes[name])
        assert list(declared) == list(part.to_dict()), name
        for field, type_name in declared.items():
            # A list of parts (list[ImportedFactor]) is a list.
            assert type(getattr(part, field)).__name__ == type_name.split("[")[0], (name, field)


def test_the_stubs_list_every_key_of_simulate_json():
    classes = stub_classes()
    result = emrm.simulate(speed_kph=72, ttc_s=0.3)  # an R cell: certificate, mitigation evidence
    printed = result.to_dict()
    assert set(members(classes["CellResult"])) == set(printed)
    outcome_keys = set().union(*(fields.keys() for fields in printed["strategies"].values()))
    assert set(members(classes["Outcome"])) == outcome_keys | {"strategy"}
