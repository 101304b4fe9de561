"""The cell file's definition: the shipped schema and reference page are fresh; the loader and the schema agree."""

from __future__ import annotations

import copy
import json
import re
import tomllib
from pathlib import Path

import jsonschema
import pytest

from codegen.model.cell import EXAMPLES_DIR, CellError, cell_from_dict, example_cells
from codegen.model.tables import json_schema, reference_text, schema_text

ROOT = Path(__file__).parents[2]
SCHEMA_FILE = EXAMPLES_DIR / "cell.schema.json"
EXAMPLES = example_cells()
DEMO = "agv_machine_tending.toml"
FRAME = "thermometer_bench.toml"
PALLET = "pallets/eur_pallet.toml"
BELT = "conveyor/belt_pick.toml"
LASER = "laser/laser_tcp.toml"

DELETE = object()
# (example, key path, new value or DELETE): each is refused by the loader and by the schema
BAD = [
    (DEMO, "cell.name", 42),  # wrong type
    (DEMO, "cell.name", "   "),  # blank
    (DEMO, "cell.targets", []),
    (DEMO, "cell.targets", ["ur", "fanuc"]),
    (DEMO, "cell.pose_format", "euler"),
    (DEMO, "cell.colour", "red"),  # unknown key
    (DEMO, "cell.camera.angle_sign", 0),
    (DEMO, "cell.camera.angle_sign", DELETE),  # missing required key
    (DEMO, "cell.camera.focus", 1.0),
    (DEMO, "cell.limits.max_shift_mm", 0.0),
    (DEMO, "cell.limits.max_shift_mm", "10"),
    (DEMO, "cell.limits.max_rotation_deg", 180.0),
    (DEMO, "cell.limits.max_rotation_deg", DELETE),
    (DEMO, "cell.motion.speed_mm_s", 0.5),
    (DEMO, "cell.motion.speed_mm_s", 5000.5),
    (DEMO, "cell.motion.zone_mm", 200.5),
    (DEMO, "cell.motion.zone_mm", -1.0),
    (DEMO, "cell.motion.retreat_mm", 1001.0),
    (DEMO, "cell.motion.return_home", "yes"),
    (DEMO, "cell.motion.start_tolerance_deg", 0.0),
    (DEMO, "cell.motion.joint_speed_percent", 101.0),
    (DEMO, "cell.motion.jerk", 1.0),
    (DEMO, "cell.vision", {"timeout_s": 0.1}),
    (DEMO, "cell.vision", {"timeout_s": 601.0}),
    (DEMO, "cell.io.timeout_s", 0.1),
    (DEMO, "cell.io.value", 1),
    (DEMO, "cell.io.output", DELETE),
    (DEMO, "cell.io.output.ur", 8),  # beyond the UR's standard outputs
    (DEMO, "cell.io.pulse", 1),
    (DEMO, "cell.robot.joint_margin_deg", 91.0),
    (DEMO, "cell.robot.wrist_margin_deg", 0.0),  # axis 5 at 0: the wrist is ambiguous
    (DEMO, "cell.robot.wrist_margin_deg", 0.05),
    (DEMO, "cell.robot.speed", 1.0),
    (DEMO, "cell.tool.mass_kg", 0.0),
    (DEMO, "cell.tool.mass_kg", 1001.0),
    (DEMO, "cell.tool.cog_mm", [0.0, 0.0]),
    (DEMO, "cell.tool.tcp", DELETE),
    (DEMO, "cell.tool.numbered", {"kuka": 17}),
    (DEMO, "station.0.id", 0),
    (DEMO, "station.0.id", 32768),
    (DEMO, "station.0.id", "1"),
    (DEMO, "station.0.id", DELETE),
    (DEMO, "station.0.name", DELETE),
    (DEMO, "station.0.mark", DELETE),
    (DEMO, "station.0.mark", [1.0, 2.0]),
    (DEMO, "station.0.mode", "spiral"),
    (DEMO, "station.0.photo", [0.0] * 6),  # a frame station's key on a point station
    (DEMO, "station.0.poses", {}),
    (DEMO, "station.0.colour", "red"),
    (DEMO, "spare", {"a": 1}),  # unknown table
    (DEMO, "cell", DELETE),
    (FRAME, "cell.refine.max_iterations", 0),
    (FRAME, "cell.refine.max_iterations", 101),
    (FRAME, "cell.refine.tolerance_mm", 0.0),
    (FRAME, "cell.refine.steps", 1),
    (FRAME, "station.0.photo", DELETE),
    (FRAME, "station.0.base_data", 0),
    (FRAME, "station.0.mark", [0.0, 0.0, 0.0]),  # a point station's key on a frame station
    (FRAME, "cell.camera.handeye.pixel_to_mm", [[1.0, 0.0, 0.0]]),
    (PALLET, "pallet.0.layers", 0),
    (PALLET, "pallet.0.layers", 201),
    (PALLET, "pallet.0.size", [1200.0, 0.0]),
    (PALLET, "pallet.0.box", DELETE),
    (PALLET, "pallet.0.angle_sense", "left"),
    (PALLET, "pallet.0.mode", "restack"),
    (PALLET, "pallet.0.overhang_mm", 201.0),
    (PALLET, "pallet.0.support_min", 1.5),
    (PALLET, "pallet.0.pick_lift", 0.0),
    (PALLET, "pallet.0.approach_auto", "no"),
    (PALLET, "pallet.0.slip_sheet", {"every": 1, "thickness": 51.0}),
    (PALLET, "pallet.0.slip_sheet", {"every": 1}),
    (PALLET, "pallet.0.frame.origin", DELETE),
    (PALLET, "pallet.0.patterns", {"p": {"family": "spiral"}}),
    (PALLET, "pallet.0.height", 1.0),
    (PALLET, "pallet.0.io", DELETE),  # the interlocks the program waits for
    (PALLET, "pallet.0.io.pallet_present", DELETE),
    (PALLET, "pallet.0.io.timeout_s", 0.1),
    (PALLET, "pallet.0.io.part_present.kuka", 4097),
    (PALLET, "pallet.0.zone_mm", 200.5),
    (PALLET, "pallet.0.box_mass_kg", -1.0),
    (PALLET, "pallet.0.slip_sheet.lift", 0.0),
    (PALLET, "pallet.0.slip_sheet.pick", DELETE),
    (BELT, "conveyor.counter_bits", 20),
    (BELT, "conveyor.working_length_mm", 0.0),
    (BELT, "conveyor.pick.capture_mm", 51.0),
    (BELT, "conveyor.pick.part_mass_kg", DELETE),
    (BELT, "conveyor.pick.approach_dz", 0.0),
    (BELT, "conveyor.pick.place_timeout_s", 0.1),
    (BELT, "conveyor.pick.belt_speed_max_mm_s", 5001.0),
    (BELT, "conveyor.pick.tracking", {"ur": "magic"}),
    (BELT, "conveyor.pick.grip", 1.0),
    (BELT, "conveyor.belt", 1.0),
    (BELT, "conveyor.pick.timer.kuka", 65),  # beyond the controller's timers (its facts)
    (BELT, "conveyor.pick.trigger_input.ur", 8),  # beyond the UR's standard inputs
    (BELT, "conveyor.pick.unit.abb", "CNV7"),  # none of the tracking option's units
    (BELT, "conveyor.pick.encoder_inputs.ur", [7, 8]),
    (LASER, "laser.sensor_frame", DELETE),
    (LASER, "laser.pin_radius_mm", 26.0),
    (LASER, "laser.pin_radius_mm", 0.1),  # too thin for the beams
    (LASER, "laser.circle_speed_mm_s", 0.5),
    (LASER, "laser.search_speed_mm_s", 51.0),
    (LASER, "laser.depths_mm", [5.0, 201.0]),
    (LASER, "laser.beam_x", DELETE),
    (LASER, "laser.power", 1.0),
    (LASER, "laser.production_tool.kuka", 17),
    (LASER, "laser.production_tool.ur", 3),
    (LASER, "laser.production_tool.abb", "t Pin"),
    (LASER, "laser.production_tool.dtrans", "tPin"),
    (LASER, "laser.safe_height_mm", 1001.0),
]
# (example, key path, value): accepted by both (the ranges' bounds that are allowed, the defaults written out)
GOOD = [
    (DEMO, "cell.motion.speed_mm_s", 1.0),
    (DEMO, "cell.motion.speed_mm_s", 5000.0),
    (DEMO, "cell.motion.zone_mm", 200.0),
    (DEMO, "cell.motion.retreat_mm", 0.0),
    (DEMO, "cell.motion.start_tolerance_deg", 30.0),
    (DEMO, "cell.motion.joint_speed_percent", 100.0),
    (DEMO, "cell.vision", {"timeout_s": 0.2}),
    (DEMO, "cell.vision", {"timeout_s": 600.0}),
    (DEMO, "cell.io.timeout_s", 600.0),
    (DEMO, "cell.robot.joint_margin_deg", 0.0),
    (DEMO, "cell.robot.wrist_margin_deg", 90.0),
    (DEMO, "cell.robot.wrist_margin_deg", 0.1),
    (DEMO, "cell.limits.max_rotation_deg", 179.0),
    (DEMO, "cell.tool.numbered", {"kuka": 16}),
    (DEMO, "station.0.id", 32767),
    (DEMO, "station.0.mode", "point"),
    (FRAME, "cell.refine.max_iterations", 100),
    (FRAME, "station.0.base_data", 1),
    (PALLET, "pallet.0.overhang_mm", 200.0),
    (PALLET, "pallet.0.support_min", 1.0),
    (PALLET, "pallet.0.mode", "stack"),
    (PALLET, "pallet.0.zone_mm", 0.0),
    (PALLET, "pallet.0.io.timeout_s", 600.0),
    (PALLET, "pallet.0.box_mass_kg", 0.0),
    (BELT, "conveyor.pick.capture_mm", 50.0),
    (BELT, "conveyor.counter_bits", 16),
    (BELT, "conveyor.pick.timer.kuka", 64),
    (BELT, "conveyor.pick.unit.abb", "CNV6"),
    (LASER, "laser.search_speed_mm_s", 1.0),
    (LASER, "laser.production_tool.kuka", 16),
    (LASER, "laser.safe_height_mm", 1000.0),
]


def _data(example: str) -> dict:
    return tomllib.loads((EXAMPLES_DIR / example).read_text(encoding="utf-8"))


def _set(data: dict, path: str, value) -> dict:
    out = copy.deepcopy(data)
    *parents, last = path.split(".")
    node = out
    for part in parents:
        node = node[int(part)] if isinstance(node, list) else node.setdefault(part, {})
    if value is DELETE:
        del node[last]
    else:
        node[last] = value
    return out


def _loader_accepts(data: dict) -> bool:
    try:
        cell_from_dict(data, source="cell.toml")
    except CellError:
        return False
    return True


@pytest.fixture(scope="module")
def validator():
    schema = json.loads(SCHEMA_FILE.read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def test_shipped_schema_is_fresh():
    assert SCHEMA_FILE.read_text(encoding="utf-8") == schema_text(), "run: codegen schema --out " + str(SCHEMA_FILE)
    assert json.loads(schema_text()) == json_schema()


def test_reference_page_is_fresh():
    page = ROOT / "docs" / "cell-file-reference.md"
    assert page.read_text(encoding="utf-8") == reference_text(), "run: codegen schema --markdown --out " + str(page)


@pytest.mark.parametrize("example", EXAMPLES, ids=lambda p: p.relative_to(EXAMPLES_DIR).as_posix())
def test_examples_validate_and_name_the_schema(example, validator):
    lines = example.read_text(encoding="utf-8").splitlines()
    assert lines[0].startswith("#:schema ")
    assert (example.parent / lines[0].split(maxsplit=1)[1]).resolve() == SCHEMA_FILE.resolve()
    errors = [e.message for e in validator.iter_errors(tomllib.loads("\n".join(lines)))]
    assert errors == []


def test_enough_bad_cells():
    assert len(BAD) >= 20 and {example for example, _, _ in BAD} == {DEMO, FRAME, PALLET, BELT, LASER}


@pytest.mark.parametrize(("example", "path", "value"), BAD, ids=[f"{p}={v!r:.20}" for _, p, v in BAD])
def test_bad_values_name_their_key_and_the_schema_refuses_them(example, path, value, validator):
    """One declaration gives the loader's checks and the schema: each refuses the value, the loader naming its key."""
    data = _set(_data(example), path, value)
    with pytest.raises(CellError) as info:
        cell_from_dict(data, source="cell.toml")
    key = re.sub(r"\.(\d+)(?=\.|$)", r"[\1]", path)  # pallet.0.layers -> pallet[0].layers
    assert str(info.value).startswith(f"cell.toml: {key}"), str(info.value)
    assert not validator.is_valid(data), "the schema accepts it"


@pytest.mark.parametrize(("example", "path", "value"), GOOD, ids=[f"{p}={v!r:.20}" for _, p, v in GOOD])
def test_good_variants_accepted_by_both(example, path, value, validator):
    data = _set(_data(example), path, value)
    assert _loader_accepts(data), "the loader refuses it"
    assert [e.message for e in validator.iter_errors(data)] == []
