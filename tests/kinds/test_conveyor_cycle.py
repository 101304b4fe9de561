"""The pick cycle a commissioning engineer loads: the carried payload, blends on travel moves only, the way home from
anywhere, a part held at the start put down at the place, the place's interlock; each change verify must catch."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from support.programs import edited, first, regex_edit, run_case, verify_one

from codegen.controllers import get_target
from codegen.kinds.conveyor.cases import cases
from codegen.kinds.conveyor.plan import carried
from codegen.kinds.conveyor.start import start_joints
from codegen.model.cell import load_cell

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"
NOMINAL = frozenset({"nominal"})

# (what, target, pattern, replacement, the scenarios that show it, what the verdict says)
CHANGES = [
    # the tool with the part after the grip confirmed: dropped
    ("held payload", "ur", r"^    set_target_payload\(2\.000, [^\n]*# the tool and the part\n", "", NOMINAL, "payload"),
    ("held payload", "kuka", r"^  \$LOAD = CNV_LOAD_HELD ; confirmed[^\n]*\n", "", NOMINAL, "payload"),
    ("held payload", "abb", r"    ! confirmed: the payload now\n    GripLoad cnv_part;\n", "", NOMINAL, "payload"),
    # the tool alone again after the release confirmed: dropped
    (
        "payload back",
        "ur",
        r"^    set_target_payload\(1\.200, [^\n]*# the tool alone\n  end\n\n  def",
        "  end\n\n  def",
        NOMINAL,
        "payload",
    ),
    # the release's (CNV_RELEASE, which stops on a gripper that does not let go), not the failed grip's let-go
    (
        "payload back",
        "kuka",
        r"(CNV_HALT\(\)\n      RETURN FALSE\n    ENDIF\n    WAIT SEC [^\n]*\n    POLLS = POLLS \+ 1\n  ENDWHILE\n)"
        r"  \$LOAD = LOAD_DATA\[\d+\] ; confirmed[^\n]*\n",
        r"\1",
        NOMINAL,
        "payload",
    ),
    ("payload back", "abb", r"    ! confirmed: the payload now\n    GripLoad load0;\n", "", NOMINAL, "payload"),
    # no way home: from away straight home (the arm would sweep through the cell with the tool down)
    ("way home", "ur", r"  if cnv_away:\n", "  if False:\n", frozenset({"start_away"}), "fit no pick"),
    ("way home", "kuka", r"  IF AWAY THEN\n", "  IF FALSE THEN\n", frozenset({"start_away"}), "fit no pick"),
    ("way home", "abb", r"    IF away THEN\n", "    IF FALSE THEN\n", frozenset({"start_away"}), "fit no pick"),
    # the part held at the start opened on at home (the old program's release at the start)
    (
        "held at start",
        "ur",
        r"  if cnv_held:\n",
        "  if False:\n",
        frozenset({"start_mid_cycle"}),
        "",
    ),
    (
        "held at start",
        "kuka",
        r"  IF HELD THEN\n",
        "  IF FALSE THEN\n",
        frozenset({"start_mid_cycle"}),
        "",
    ),
    (
        "held at start",
        "abb",
        r"    IF held THEN\n      ! the grip",
        "    IF FALSE THEN\n      ! the grip",
        frozenset({"start_mid_cycle"}),
        "",
    ),
    # the place's interlock not asked
    (
        "interlock",
        "ur",
        r"while not get_standard_digital_in\(2\):",
        "while False:",
        frozenset({"device_silent"}),
        "expected a stop",
    ),
    (
        "interlock",
        "kuka",
        r"WHILE NOT \$IN\[19\] ; the place is clear",
        "WHILE FALSE",
        frozenset({"device_silent"}),
        "expected a stop",
    ),
    (
        "interlock",
        "abb",
        r"    WaitDI diCnvPlaceClear, 1 \\MaxTime:=CNV_PLACE_TIMEOUT;\n",
        "",
        frozenset({"device_silent"}),
        "expected a stop",
    ),
    # a blend where the arm must stop: at the place
    (
        "blend at the place",
        "ur",
        r"movel\(CNV_PLACE, a=1\.200, v=0\.2500\)",
        "movel(CNV_PLACE, a=1.200, v=0.2500, r=0.0100)",
        NOMINAL,
        "must stop exactly",
    ),
    ("blend at the place", "kuka", r"^  LIN CNV_PLACE\n", "  LIN CNV_PLACE C_DIS\n", NOMINAL, "must stop exactly"),
    (
        "blend at the place",
        "abb",
        r"MoveL cnv_place, cnv_work, fine",
        "MoveL cnv_place, cnv_work, cnv_zone",
        NOMINAL,
        "must stop exactly",
    ),
    # a travel move that stops where the plan blends it (cycle time)
    ("no blend", "kuka", r"LIN LIFTED C_DIS", "LIN LIFTED", NOMINAL, "expected"),
    ("no blend", "abb", r"MoveL above, cnv_work, cnv_zone", "MoveL above, cnv_work, fine", NOMINAL, "expected"),
]


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


@pytest.mark.parametrize(("what", "target", "pattern", "replacement", "scenarios", "says"), CHANGES)
def test_a_program_without_it_fails_verify(cell, what, target, pattern, replacement, scenarios, says):
    program = first(cell, target, "conveyor")
    mutant = edited(program, regex_edit(pattern, replacement), what.replace(" ", "_"))
    row = verify_one(cell, mutant, first_mismatch=True, scenarios=scenarios)
    assert row.mismatches > 0, f"verify missed {what} on {target}"
    assert any(says in m for m in row.first_mismatches), row.first_mismatches


def test_the_payload_held_is_the_tool_and_the_part_at_the_flange(cell):
    """0.8 kg 20 mm beyond the TCP (150 mm along the flange's z) with the tool's 1.2 kg at 60 mm: 2 kg at 104 mm; the
    tool a solid cylinder of radius 25 mm from the flange to the TCP, the part a solid box of part_size_mm along the
    tool's axes, each with its parallel-axis term to the common centre (kg m2)."""
    a, b, c = (v / 1000.0 for v in cell.sections["conveyor"].pick.part_size_mm)
    side, axis = 1.2 * (3 * 0.025**2 + 0.15**2) / 12, 1.2 * 0.025**2 / 2
    d_tool, d_part = 0.104 - 0.060, 0.170 - 0.104
    ixx = side + 1.2 * d_tool**2 + 0.8 * (b * b + c * c) / 12 + 0.8 * d_part**2
    iyy = side + 1.2 * d_tool**2 + 0.8 * (a * a + c * c) / 12 + 0.8 * d_part**2
    izz = axis + 0.8 * (a * a + b * b) / 12
    expected = (2.0, 0.0, 0.0, (1.2 * 60.0 + 0.8 * 170.0) / 2.0, ixx, iyy, izz, 0.0, 0.0, 0.0)
    assert carried(cell) == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("target", ["ur", "kuka", "abb"])
def test_a_part_held_at_a_stop_mid_cycle_goes_home_and_to_the_place_first(cell, target):
    """From above the belt, holding a part: back out 60 mm along the tool's axis, the safe pose, home, then the
    place, where the gripper opens (the grip set again before any motion, then the release), and on to the next part;
    the payload is the part's from the first move to the place."""
    case = next(c for c in cases(cell) if c.category == "start_mid_cycle")
    program = first(cell, target, "conveyor").load()
    trace, _setup = run_case(cell, target, program, case, "conveyor")
    assert not trace.halted
    stands, back = trace.moves[0].tcp2base, trace.moves[1].tcp2base
    assert back[:3, 3] - stands[:3, 3] == pytest.approx(-60.0 * stands[:3, 2], abs=0.01)  # along the tool's -z
    place = cell.sections["conveyor"].pick.place.matrix()
    gripper = {"ur": "standard_digital_out[0]", "kuka": "$OUT[17]", "abb": "doGripClose"}[target]
    again, release = [o for o in trace.outputs if o.name == gripper][:2]  # ABB pulses c1RemAllPObj before any move
    assert again.value is True and again.after_moves == 0  # before any motion: the way home would drop the part
    assert release.value is False and release.after_moves == 6
    assert trace.moves[5].tcp2base[:3, 3] == pytest.approx(place[:3, 3], abs=0.01)
    held = [m.settings["load"] for m in trace.moves[:6]]
    assert all(load == pytest.approx(carried(cell), abs=1e-3) for load in held)
    joints = np.asarray(start_joints(cell, target, "mid_cycle"))
    assert trace.moves[0].joints == pytest.approx(joints, abs=0.05)
    assert get_target(target).name == target
