"""A KUKA pallet cell's joint margins and flips as generate and verify report them: the joint that flips, named."""

from __future__ import annotations

import re
from pathlib import Path

from click.testing import CliRunner

from codegen.cli import main

CARTON = (Path(__file__).resolve().parent / "cells" / "carton_kuka.toml").read_text(encoding="utf-8")
PICK = "pick = [1300.0, 0.0, 150.0, 0.0, 0.0, 180.0]"


def test_a_flip_on_a_linear_move_names_the_axis_its_values_and_the_key(tmp_path):
    """Q low and near the base: the way up from Q (a linear move) straightens the wrist, axis 5 passes 0 deg. The
    refusal names the axis, where it starts and ends, and the key that moves Q, not only "a wrist or elbow flip"."""
    assert PICK in CARTON
    path = tmp_path / "carton.toml"
    path.write_text(CARTON.replace(PICK, "pick = [900.0, 0.0, -550.0, 0.0, 0.0, 180.0]"), encoding="utf-8")
    result = CliRunner().invoke(main, ["generate", str(path), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "layer 2 box 1 up from Q" in result.output
    found = re.search(r"axis 5 crosses its singularity \(the wrist straight\): from (\S+) to (\S+) deg", result.output)
    assert found, result.output
    before, after = float(found[1]), float(found[2])
    assert before * after < 0  # on either side of 0 deg, where the KUKA's wrist is straight
    assert "[[pallet]] pick" in result.output
    assert "Traceback" not in result.output
