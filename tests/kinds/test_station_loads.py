"""A station's part as a load: [station.part] mass_kg and cog_mm read and refused by key, the tool's and the part's
load as one, and a station program whose part load leaves out the inertia, is never switched on, stays on after the
release, or whose release is moved from a place pose to the travel, failing verify for that reason."""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest
from support import stations
from support.cells import example
from support.programs import edited, regex_edit, run_case, sources, verify

from codegen.kinds.station.cases import Case
from codegen.kinds.station.part import held_part, part_alone, part_load
from codegen.kinds.station.point.reference import Reading
from codegen.kinds.station.section import stations_of
from codegen.model.cell import CellError, cell_from_dict, load_cell

DEMO = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "agv_machine_tending.toml"
BENCH = DEMO.parent / "thermometer_bench.toml"
NUMBER = r"-?\d+\.\d+"


def _demo() -> dict:
    return tomllib.loads(DEMO.read_text(encoding="utf-8"))


def _tensor_by_hand(tool_kg, tool_cog_z, radius, length, part_kg, part_centre_z, size) -> tuple[float, ...]:
    """A cylinder tool along z and a box part below it, both on the flange's z axis, written out term by term
    (kg, mm -> kg m2): each solid's own moments, then m d^2 to the common centre (the z axis passes through both)."""
    mass = tool_kg + part_kg
    cog = (tool_kg * tool_cog_z + part_kg * part_centre_z) / mass
    tool_side = tool_kg * (3 * radius**2 + length**2) / 12
    tool_axial = tool_kg * radius**2 / 2
    x, y, z = size
    part_xx, part_yy, part_zz = part_kg * (y**2 + z**2) / 12, part_kg * (x**2 + z**2) / 12, part_kg * (x**2 + y**2) / 12
    shift = tool_kg * (tool_cog_z - cog) ** 2 + part_kg * (part_centre_z - cog) ** 2
    ixx = (tool_side + part_xx + shift) * 1e-6
    iyy = (tool_side + part_yy + shift) * 1e-6
    izz = (tool_axial + part_zz) * 1e-6
    return mass, 0.0, 0.0, cog, ixx, iyy, izz, 0.0, 0.0, 0.0


def test_the_demo_parts_load_is_the_tools_and_the_parts_as_one():
    """1.5 kg tool (a 25 mm x 200 mm cylinder, centre of gravity 80 mm out) and a 2.26 kg 60 x 60 x 80 mm part
    hanging from the TCP 200 mm out: 3.76 kg at 176.17 mm, the parallel-axis terms included."""
    cell = load_cell(DEMO)
    lathe = stations_of(cell)[0]
    want = _tensor_by_hand(1.5, 80.0, 25.0, 200.0, 2.26, 240.0, (60.0, 60.0, 80.0))
    np.testing.assert_allclose(part_load(cell, lathe).flat(), want, rtol=1e-12, atol=1e-15)
    alone = part_alone(lathe.part)  # in the TCP frame: what a RAPID GripLoad takes
    np.testing.assert_allclose(alone.cog_mm, (0.0, 0.0, 40.0))
    inspection = stations_of(cell)[5]
    assert inspection.part is None and part_load(cell, inspection) is None


def test_a_declared_centre_of_gravity_moves_the_load():
    data = _demo()
    data["station"][0]["part"]["cog_mm"] = [10.0, 0.0, 30.0]
    cell = cell_from_dict(data, "cell.toml")
    load = part_load(cell, stations_of(cell)[0])
    np.testing.assert_allclose(load.cog_mm, (2.26 * 10.0 / 3.76, 0.0, (1.5 * 80.0 + 2.26 * 230.0) / 3.76))


def test_a_part_without_mass_leaves_the_tools_load():
    data = _demo()
    del data["station"][0]["part"]["mass_kg"]
    cell = cell_from_dict(data, "cell.toml")
    assert stations_of(cell)[0].part.mass_kg == 0.0 and part_load(cell, stations_of(cell)[0]) is None


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("-1.0", r"line \d+: station\[0\]\.part\.mass_kg: must be in \[0, 2000\] kg"),
        ('"heavy"', r"line \d+: station\[0\]\.part\.mass_kg: expected a number"),
        ("12.0", r"line \d+: station\[0\]\.part\.mass_kg: 12 kg carried by a 1\.5 kg tool is more than the \w+"),
    ],
)
def test_a_bad_part_mass_names_its_line_and_key(tmp_path, value, message):
    text = DEMO.read_text(encoding="utf-8").replace("mass_kg = 2.26 ", f"mass_kg = {value} ", 1)
    path = tmp_path / "cell.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(CellError, match=message):
        load_cell(path)


# --- the programs: each edit must fail verify -----------------------------------------------------------------

# the part's load (the tool's and the part's; ABB: the part's own loaddata) with its inertia zeroed, every station
ZERO_INERTIA = {
    "ur": (r"(set_target_payload\([^\n]*\], )\[[^\]]*\]\)(   # the tool and the part)", r"\1[0, 0, 0, 0, 0, 0])\2"),
    "kuka": (rf"(VIS_LOAD_\d+=[^\n]*)J \{{X {NUMBER},Y {NUMBER},Z {NUMBER}\}}", r"\1J {X 0.0,Y 0.0,Z 0.0}"),
    "abb": (rf"(vis_part_\d+ := \[[^\n]*\[{NUMBER}, {NUMBER}, {NUMBER}, {NUMBER}\]), [^\]]*\]", r"\1, 0, 0, 0]"),
}
# the switch to the tool and the part at each confirmed grip removed: the part is carried with the tool's load
NEVER_ON = {
    "ur": (r"^\s*set_target_payload\([^\n]*# the tool and the part\n", ""),
    "kuka": (r"^\s*\$LOAD = VIS_LOAD_\d+\n", ""),
    "abb": (r"^\s*GripLoad vis_part_\d+;\n", ""),
}
# the switch back to the tool alone after each confirmed release removed: the part's load stays on
KEPT_AFTER_RELEASE = {
    "ur": (r"^\s*set_target_payload\([^\n]*# the tool alone\n", ""),
    "kuka": (r"(ENDIF\n)\s*\$LOAD = VIS_LOAD\n", r"\1"),
    "abb": (r"^\s*GripLoad load0;\n", ""),
}
# the first release alone moved past the next move (the load switched where it was): the gripper opens on the way up
# from the tray, not at the tray
RELEASE_ON_THE_WAY = {
    "ur": (r"(\n\s*vis_release\(\))(\n[^\n]*# the tool alone\n\s*movel\([^\n]*\))", r"\2\1"),
    "kuka": (
        r"(\n  IF NOT VIS_RELEASE\(\) THEN\n    RETURN\n  ENDIF)"
        r"(\n  \$LOAD = VIS_LOAD\n  TARGET = [^\n]*\n  \$VEL\.CP = [^\n]*\n  LIN [^\n]*)",
        r"\2\1",
    ),
    "abb": (r"(\n\s*vis_release;)(\n\s*GripLoad load0;\n\s*ConfL \\Off;\n\s*MoveL [^\n]*)", r"\2\1"),
    "dtrans": (r"(\n\s*Call vis_release\(\))(\n\s*MovL [^\n]*)", r"\2\1"),
}


def first_mismatch(target: str, pattern: tuple[str, str], count: int = 0) -> str:
    cell = example("agv_machine_tending")
    (program,) = sources(cell, target, "station")[:1]
    mutant = edited(program, regex_edit(*pattern, count), "mutant")
    (row,) = verify(cell, [mutant], cases=1, first_mismatch=True)
    assert row.mismatches > 0, f"verify missed the edit in the station program for {target}"
    return " ".join(row.first_mismatches)


@pytest.mark.parametrize("target", sorted(ZERO_INERTIA))
def test_a_part_load_without_its_inertia_fails_verify(target):
    problem = first_mismatch(target, ZERO_INERTIA[target])
    assert "the payload in force has the inertia" in problem, problem


@pytest.mark.parametrize("target", sorted(NEVER_ON))
def test_the_part_load_never_switched_on_fails_verify(target):
    problem = first_mismatch(target, NEVER_ON[target])
    assert "the payload in force is" in problem and "chuck_clear" in problem, problem


@pytest.mark.parametrize("target", sorted(KEPT_AFTER_RELEASE))
def test_the_part_load_kept_after_the_release_fails_verify(target):
    problem = first_mismatch(target, KEPT_AFTER_RELEASE[target])
    assert "the payload in force is" in problem and "tray_done_up" in problem, problem


@pytest.mark.parametrize("target", sorted(RELEASE_ON_THE_WAY))
def test_a_release_moved_from_its_place_to_the_travel_fails_verify(target):
    """Caught twice: the gripper's output after the wrong move (the plan's), and the part's own life: the gripper
    opened with the part away from every release pose (kinds/station/part.py), which holds without the plan."""
    problem = first_mismatch(target, RELEASE_ON_THE_WAY[target], count=1)
    assert "expected" in problem and "(release at tray_done)" in problem, problem
    cell = example("agv_machine_tending")
    source = sources(cell, target, "station")[0]
    mutant = edited(source, regex_edit(*RELEASE_ON_THE_WAY[target], 1), "mutant")
    lathe = stations_of(cell)[0]
    case = Case("zero_shift", Reading(lathe.id, *lathe.spec.mark))
    trace, setup = run_case(cell, target, mutant.load(), case, "station")
    judgement = cell.kinds["station"].verify.judge(cell, source, case, trace, setup)
    assert judgement.truth is not None and "the gripper opened with a part" in judgement.truth, judgement.truth
    assert "not put down at a release pose (tray_done, chuck)" in judgement.truth, judgement.truth
    good, good_setup = run_case(cell, target, source.load(), case, "station")
    assert cell.kinds["station"].verify.judge(cell, source, case, good, good_setup).truth is None


def test_a_part_held_at_the_start_has_its_load_before_the_station_only_where_every_part_has_one_load():
    cell = load_cell(DEMO)
    assert held_part(cell, stations_of(cell)) == stations_of(cell)[0]
    data = _demo()
    data["station"][1]["part"]["mass_kg"] = 3.0
    assert held_part(cell_from_dict(data, "cell.toml"), stations_of(cell_from_dict(data, "cell.toml"))) is None


@pytest.mark.parametrize("target", ["abb", "kuka", "ur"])
def test_parts_of_different_loads_held_at_the_start_pass_verify(target):
    """Two parts of different mass: a part held at the start gets its load once the station is known (a place-first
    station), and none before (the move home and a station that takes a part first, which stops at home)."""
    data = _demo()
    data["station"][0]["gripper"] = {"chuck": "release"}
    data["station"][1]["part"]["mass_kg"] = 3.0
    cell = cell_from_dict(data, str(DEMO))
    assert held_part(cell, stations_of(cell)) is None
    cases = [c for c in stations.build_cases(cell, 1, 3) if c.reading.station_id in (1, 2)]
    assert {"part_held", "gripper_silent", "gripper_stuck"} <= {c.category for c in cases}
    row = stations.verify(cell, stations.source(cell, target), cases)
    assert row.mismatches == 0, row.first_mismatches


@pytest.mark.parametrize("target", ["abb", "kuka", "ur"])
def test_a_part_carried_into_a_frame_station_has_its_load(target):
    """The frame-mode bench as two runs (a tray station takes a thermometer, a frame station puts it into the bath's
    cavity after its photos): the load follows the part through the photo moves too."""
    data = tomllib.loads(BENCH.read_text(encoding="utf-8"))
    data["cell"]["io"] = _demo()["cell"]["io"]
    data["station"][0]["gripper"] = {"cavity": "release"}
    data["station"][1]["gripper"] = {"slot": "grip"}
    for station in data["station"][:2]:
        station["part"] = {"size_mm": [10.0, 10.0, 30.0], "mass_kg": 0.2}
    cell = cell_from_dict(data, str(BENCH))
    assert all(part_load(cell, s) is not None for s in stations_of(cell)[:2])
    source = stations.source(cell, target)
    switches = ("GripLoad vis_part_", "$LOAD = VIS_LOAD_", "# the tool and the part")
    assert any(word in f.text for f in source.files for word in switches)
    cases = [c for c in stations.build_cases(cell, 1, 3) if c.category != "unknown_station"]
    row = stations.verify(cell, source, cases)
    assert row.mismatches == 0, row.first_mismatches
