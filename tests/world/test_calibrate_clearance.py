"""`calibrate ... --write CELL` proves the edited cell's moves clear of its solids as generate does: a cell whose
moves would cut a solid is refused with generate's own words, the file left as it was."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from click.testing import CliRunner

from codegen.cli import main
from codegen.generate import GenerateError, check_clearance
from codegen.model.cell import EXAMPLES_DIR, load_cell

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "kinds"))
from test_calibrate_tcp import tilts, touch, write_csv  # the tool calibration's touches (tests/kinds)

BELT_CELL = EXAMPLES_DIR / "conveyor" / "belt_pick.toml"
# a plate across the way down to the belt's place (400, 800, 400) mm, 30 mm above it: the tool passes through it
PLATE = "[cell.world]\nsolids.plate = { box = [120.0, 120.0, 10.0], pose = [400.0, 800.0, 430.0, 0.0, 0.0, 0.0] }\n\n"


def test_a_calibration_into_a_cell_whose_moves_cut_a_solid_is_refused_as_generate_refuses_it(tmp_path):
    cell = tmp_path / "cell.toml"
    text = BELT_CELL.read_text(encoding="utf-8")
    cell.write_text(text.replace("[cell.io]", PLATE + "[cell.io]", 1), encoding="utf-8")
    before = cell.read_bytes()
    try:
        check_clearance(load_cell(cell), None)
    except GenerateError as exc:
        refusal = str(exc)
    else:
        raise AssertionError("generate proves the plate's cell clear")
    assert "'plate'" in refusal
    touches = write_csv(tmp_path, [touch(t, tcp=np.array([0.0, 0.0, 150.0])) for t in tilts(40)], name="tool.csv")
    result = CliRunner().invoke(main, ["calibrate", "tcp", str(touches), "--write", str(cell)])
    assert result.exit_code == 2 and "Traceback" not in result.output, result.output
    errors = [line for line in result.output.splitlines() if line.strip()]
    assert len(errors) == 1 and errors[0].endswith(f"{cell}: with this tool the cell would not generate: {refusal}")
    assert cell.read_bytes() == before
