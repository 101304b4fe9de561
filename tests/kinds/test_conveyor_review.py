"""The belt programs as a vendor's engineer reads them: names, routines that move, waits, blends, payloads."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from support.programs import edited, first, run_case

from codegen.controllers import get_target
from codegen.dialects.core.values import RunError
from codegen.kinds.conveyor import plan
from codegen.kinds.conveyor.cases import cases
from codegen.model.cell import load_cell

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"
MOTION = re.compile(r"^\s*(PTP|LIN|CIRC|SPTP|SLIN|SCIRC|PTP_REL|LIN_REL)\b", re.MULTILINE)


@pytest.fixture(scope="module")
def cell():
    return load_cell(CELL)


def _src(cell) -> str:
    return next(f.text for f in first(cell, "kuka", "conveyor").files if f.name.endswith(".src"))


def test_no_kuka_variable_takes_a_data_types_name(cell):
    """AXIS is one of KSS's own structure types: the program's counter has a name of its own, and a program that
    declares a variable AXIS is refused when it loads."""
    program = first(cell, "kuka", "conveyor")
    program.load()
    mutant = edited(program, lambda text: re.sub(r"\bN_AX\b", "AXIS", text))
    with pytest.raises(RunError, match="AXIS is the name of a data type"):
        mutant.load()


def test_no_kuka_function_moves_the_arm(cell):
    """A function (DEFFCT) is called inside an expression: the routines that move the arm are DEF routines."""
    functions = re.findall(r"^DEFFCT\b.*?^ENDFCT", _src(cell), re.MULTILINE | re.DOTALL)
    assert functions
    moving = [f.splitlines()[0] for f in functions if MOTION.search(f)]
    assert not moving, moving
    assert re.search(r"^DEF CNV_PLACE_PART\(PLACED:OUT\)", _src(cell), re.MULTILINE)


@pytest.mark.parametrize("target", ["ur", "kuka", "abb"])
def test_no_move_blends_into_a_wait_or_an_output(target):
    """The moves after which the program waits or sets the gripper stop there (no zone, r 0), on every target."""
    listed = get_target(target).kind_tables["conveyor"].get("blends", {})
    for mode, keys in listed.items():
        assert not set(keys) & plan.WAITS_AFTER[mode], (target, mode, keys)
        assert set(keys) <= {s.key for s in plan.PICK[mode]}


@pytest.mark.parametrize("target", ["ur", "kuka", "abb"])
def test_no_blend_is_longer_than_half_of_either_move_it_joins(cell, target):
    """Blends cannot overlap (UR user manual, blend parameters): on the nominal run every blended move's zone is at
    most half the move and half the next one."""
    case = next(c for c in cases(cell) if c.category == "constant_speed")
    trace, _setup = run_case(cell, target, first(cell, target, "conveyor").load(), case, "conveyor")
    zone = cell.motion.zone_mm
    blended = [i for i, m in enumerate(trace.moves) if _zone(m.settings) > 0 and 0 < i < len(trace.moves) - 1]
    assert blended or target == "ur"
    for i in blended:
        before = np.linalg.norm(trace.moves[i].tcp2base[:3, 3] - trace.moves[i - 1].tcp2base[:3, 3])
        after = np.linalg.norm(trace.moves[i + 1].tcp2base[:3, 3] - trace.moves[i].tcp2base[:3, 3])
        assert zone <= 0.5 * min(before, after), (target, i, trace.moves[i].line, before, after)


def _zone(settings: dict) -> float:
    """The move's blend (mm) as the dialect records it."""
    for key, scale in (("r", 1000.0), ("cdis", 1.0), ("zone_mm", 1.0)):
        value = settings.get(key)
        if isinstance(value, int | float) and value:
            return float(value) * scale
    return 0.0


def test_the_abb_parts_load_has_the_inertia_of_its_box(cell):
    """0.8 kg, 120 x 80 x 40 mm: ix = 0.8 (0.08^2 + 0.04^2) / 12, iy = 0.8 (0.12^2 + 0.04^2) / 12, iz = 0.8 (0.12^2 +
    0.08^2) / 12 kg m2 (a solid box about its centre of gravity)."""
    text = first(cell, "abb", "conveyor").files[0].text
    line = next(x for x in text.splitlines() if "loaddata cnv_part" in x)
    ix, iy, iz = (float(v) for v in line.rstrip("];").split(",")[-3:])
    assert (ix, iy, iz) == pytest.approx((0.000533, 0.001067, 0.001387), abs=1e-6)
