"""The tool's shape in [cell.tool] gives its inertia; a tool without one is a point mass, said once as a warning and
in the programs' load comments."""

from __future__ import annotations

import pytest
from support.cells import EXAMPLES

from codegen.model.cell import CellError, load_cell
from codegen.render import render

SHAPE_LINE = "radius_mm = 25.0"


def demo(tmp_path, old: str, new: str):
    text = EXAMPLES["agv_machine_tending"].read_text(encoding="utf-8")
    line = next(li for li in text.splitlines() if li.startswith(old))
    path = tmp_path / "agv_machine_tending.toml"
    path.write_text(text.replace(line, new, 1), encoding="utf-8")
    return path


def files_of(cell) -> dict[str, str]:
    return {f.relpath.rsplit("/", 1)[-1]: f.text for f in render(cell, ["ur", "kuka", "abb"])}


def test_a_tool_without_a_shape_is_a_point_mass_with_a_warning(tmp_path):
    cell = load_cell(demo(tmp_path, SHAPE_LINE, ""))
    assert [w for w in cell.warnings if "cell.tool: no shape" in w and "point mass" in w]
    files = files_of(cell)
    ur, dat, mod = (files[f"agv_machine_tending.{suffix}"] for suffix in ("script", "dat", "mod"))
    assert "[0.000000, 0.000000, 0.000000, 0.000000, 0.000000, 0.000000])" in ur
    assert "J {X 0.000000,Y 0.000000,Z 0.000000}" in dat and "a point mass: [cell.tool] gives no shape" in dat
    assert "[1.000000, 0.000000, 0.000000, 0.000000], 0.000000, 0.000000, 0.000000]]" in mod


def test_a_box_tool_gives_the_boxs_moments(tmp_path):
    """1.5 kg, 40 x 60 mm across and 200 mm from the flange to the TCP: (m / 12) (b2 + c2) about each axis."""
    cell = load_cell(demo(tmp_path, SHAPE_LINE, "box_mm = [40.0, 60.0]"))
    assert not [w for w in cell.warnings if "cell.tool" in w]
    m, a, b, c = 1.5, 0.04, 0.06, 0.2
    moments = sorted([m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12])
    dat = files_of(cell)["agv_machine_tending.dat"]
    line = next(li for li in dat.splitlines() if li.startswith("DECL LOAD VIS_LOAD="))
    j = line.split("J {", 1)[1].rstrip("}").split(",")
    assert sorted(float(v.split()[1]) for v in j) == pytest.approx(moments, abs=5e-7)


def test_a_tool_is_a_cylinder_or_a_box_not_both(tmp_path):
    with pytest.raises(CellError, match=r"cell.tool.box_mm: the tool is a cylinder \(radius_mm\) or a box"):
        load_cell(demo(tmp_path, SHAPE_LINE, SHAPE_LINE + "\nbox_mm = [40.0, 60.0]"))
