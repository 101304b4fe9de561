"""[cell.world] and [station.part] read from the cell file, and a cell's solids for one target's arm: the floor, the
declared solids and every kind's own, the tool and the carried part, each distance measured against the geometry."""

from __future__ import annotations

import numpy as np
import pytest
from support.cells import EXAMPLES

from codegen.model.cell import CellError, load_cell
from codegen.world.cell import FLOOR, clearance_mm, scene_of, solids
from codegen.world.solids import Box, Cylinder, Floor, translation

TOOL_LINE = "radius_mm = 25.0"


def demo(tmp_path, after: str, extra: str):
    """The demo cell without its [cell.world] table, `extra` lines put after the first line that starts with `after`."""
    text = EXAMPLES["agv_machine_tending"].read_text(encoding="utf-8")
    start = text.index("[cell.world]")
    text = text[:start] + text[text.index("\n\n", start) + 2 :]
    line = next(li for li in text.splitlines() if li.startswith(after))
    path = tmp_path / "agv_machine_tending.toml"
    path.write_text(text.replace(line, line + "\n" + extra, 1), encoding="utf-8")
    return path


WORLD = """
[cell.world]
floor_z_mm = -100.0
clearance_mm = 30.0
solids.pillar = { cylinder = [50.0, 2000.0], pose = [1000.0, 0.0, 1000.0, 0.0, 0.0, 0.0] }
solids.fence = { box = [20.0, 3000.0, 2000.0], pose = [-900.0, 0.0, 1000.0, 0.0, 0.0, 0.0] }
"""


def test_a_cell_without_the_table_has_the_mounting_plane_for_its_floor_and_the_default_clearance(tmp_path):
    cell = load_cell(demo(tmp_path, TOOL_LINE, ""))
    world = solids(cell)
    assert isinstance(world[FLOOR], Floor) and world[FLOOR].height == 0.0
    assert clearance_mm(cell) == 20.0


def test_the_default_clearance_is_the_sweeps():
    from codegen.model.world import CLEARANCE_DEFAULT_MM
    from codegen.world.sweep import CLEARANCE_MM

    assert CLEARANCE_DEFAULT_MM == CLEARANCE_MM


def test_declared_solids_stand_where_the_cell_puts_them(tmp_path):
    cell = load_cell(demo(tmp_path, TOOL_LINE, WORLD))
    assert clearance_mm(cell) == 30.0
    world = solids(cell)
    assert world[FLOOR].height == -100.0
    pillar, fence = world["pillar"], world["fence"]
    assert isinstance(pillar, Cylinder) and (pillar.radius, pillar.length) == (50.0, 2000.0)
    assert np.allclose(pillar.pose[:3, 3], (1000.0, 0.0, 1000.0))
    assert isinstance(fence, Box) and fence.size == (20.0, 3000.0, 2000.0)


def test_a_declared_solid_under_the_tool_is_as_far_as_its_face(tmp_path):
    """The demo's UR10e at its home, the tool (a 25 mm cylinder, 200 mm) pointing down: a 400 mm cube whose top face
    lies 15 mm under the TCP is 15 mm from the tool, and the nearest body to it is the tool."""
    arm = load_cell(EXAMPLES["agv_machine_tending"]).robot.arms["ur"]
    joints = np.array([180.0, -90.0, 90.0, -90.0, -90.0, 0.0])
    tcp = arm.kin.fk(joints) @ np.array([0.0, 0.0, 200.0, 1.0])
    centre = tcp[:3] - (0.0, 0.0, 15.0 + 200.0)
    pose = "[" + ", ".join(repr(float(v)) for v in centre) + ", 0.0, 0.0, 0.0]"
    cell = load_cell(
        demo(
            tmp_path,
            TOOL_LINE,
            f"[cell.world]\nfloor_z_mm = -2000.0\nsolids.cube = {{ box = [400.0, 400.0, 400.0], pose = {pose} }}",
        )
    )
    found = scene_of(cell, "ur").nearest(joints[None])[0]
    assert (found.body, found.other) == ("tool", "cube")
    assert found.distance == pytest.approx(15.0, abs=1e-6)


def test_a_part_hangs_from_the_tcp(tmp_path):
    """A 100 mm cube under the demo's 200 mm tool: its bottom 300 mm from the flange along the tool's z; a floor raised
    to 10 mm under that bottom is 10 mm from the part, nearer than any other body."""
    from codegen.model.world import PartShape

    arm = load_cell(EXAMPLES["agv_machine_tending"]).robot.arms["ur"]
    joints = np.array([0.0, -60.0, 90.0, -120.0, -90.0, 0.0])  # the tool down, 309 mm above the base
    bottom = (arm.kin.fk(joints) @ np.array([0.0, 0.0, 300.0, 1.0]))[2]
    cell = load_cell(demo(tmp_path, TOOL_LINE, f"[cell.world]\nfloor_z_mm = {float(bottom - 10.0)!r}"))
    scene = scene_of(cell, "ur", PartShape((100.0, 100.0, 100.0)))
    assert [b.name for b in scene.bodies][-2:] == ["tool", "part"]
    found = scene.nearest(joints[None])[0]
    assert (found.body, found.other) == ("part", FLOOR)
    assert found.distance == pytest.approx(10.0, abs=1e-6)


def test_the_kinds_add_their_own_solids():
    cells = {name: load_cell(path) for name, path in EXAMPLES.items()}
    assert {"pallet eur", "pallet eur: pick place"} <= set(solids(cells["eur_pallet"]))
    assert {"belt", "belt: place table"} <= set(solids(cells["belt_pick"]))
    assert {"sensor X", "sensor Y"} <= set(solids(cells["laser_tcp"]))


def test_a_pallets_solid_lies_under_its_top(tmp_path):
    from codegen.kinds.pallet.analysis import frame_matrix
    from codegen.kinds.pallet.section import pallets_of

    cell = load_cell(EXAMPLES["eur_pallet"])
    pallet = pallets_of(cell)[0]
    solid = solids(cell)[f"pallet {pallet.name}"]
    top_centre = frame_matrix(pallet) @ np.array([pallet.size[0] / 2, pallet.size[1] / 2, 0.0, 1.0])
    # the solid's top face's centre is the pallet's top centre: half its height above the solid's centre
    face = solid.pose @ np.array([0.0, 0.0, solid.size[2] / 2, 1.0])
    assert np.allclose(face, top_centre, atol=1e-9)


@pytest.mark.parametrize(
    ("extra", "key", "said"),
    [
        ("[cell.world]\nclearance_mm = 0.0", "cell.world.clearance_mm", "must be"),
        ("[cell.world]\nfloor_z_mm = nan", "cell.world.floor_z_mm", "finite"),
        (
            "[cell.world]\nsolids.a = { box = [1.0, -2.0, 3.0], pose = [0, 0, 0, 0, 0, 0] }",
            "cell.world.solids.a.box",
            "",
        ),
        ("[cell.world]\nsolids.a = { pose = [0, 0, 0, 0, 0, 0] }", "cell.world.solids.a", "neither"),
        (
            "[cell.world]\nsolids.a = { box = [1, 2, 3], cylinder = [1, 2], pose = [0, 0, 0, 0, 0, 0] }",
            "cell.world.solids.a",
            "both",
        ),
        ("[cell.world]\nsolids.a = { box = [1, 2, 3] }", "cell.world.solids.a.pose", "missing"),
        (
            "[cell.world]\nsolids.a = { box = [1, 2, 3], pose = [0, 0, 0, 0, 0, 0], colour = 1 }",
            "cell.world.solids.a",
            "unknown",
        ),
        ("[cell.world]\nwalls = 1", "cell.world", "unknown"),
    ],
)
def test_bad_world_keys_are_named(tmp_path, extra, key, said):
    with pytest.raises(CellError) as caught:
        load_cell(demo(tmp_path, TOOL_LINE, extra))
    assert key in str(caught.value) and said in str(caught.value)
    assert "line" in str(caught.value)


def test_a_station_part_and_solids_are_read(tmp_path):
    from codegen.kinds.station.section import stations_of

    station = stations_of(load_cell(EXAMPLES["agv_machine_tending"]))[0]
    assert station.part.size_mm == (60.0, 60.0, 80.0)
    assert station.solids["bed"].size == (200.0, 300.0, 595.2)
    text = EXAMPLES["agv_machine_tending"].read_text(encoding="utf-8")
    path = tmp_path / "c.toml"
    path.write_text(text.replace("size_mm = [60.0, 60.0, 80.0]", "size_mm = [60.0, 0.0, 80.0]", 1), encoding="utf-8")
    with pytest.raises(CellError, match=r"station\[0\].part.size_mm"):
        load_cell(path)
    bed = next(line for line in text.splitlines() if line.startswith("bed = "))
    path.write_text(text.replace(bed, "bed = { pose = [0, 0, 0, 0, 0, 0] }", 1), encoding="utf-8")
    with pytest.raises(CellError, match=r"station\[0\].solids.bed: .* neither"):
        load_cell(path)


def test_a_declared_solid_may_not_take_a_kinds_name(tmp_path):
    text = EXAMPLES["eur_pallet"].read_text(encoding="utf-8")
    path = tmp_path / "c.toml"
    marker = "[cell.world]"
    extra = '\nsolids."pallet eur" = { box = [1, 2, 3], pose = [0, 0, 0, 0, 0, 0] }'
    path.write_text(text.replace(marker, marker + extra, 1), encoding="utf-8")
    with pytest.raises(ValueError, match="pallet eur"):
        solids(load_cell(path))


def test_translation_is_a_pose():
    assert np.allclose(translation(1, 2, 3)[:3, 3], (1, 2, 3))
