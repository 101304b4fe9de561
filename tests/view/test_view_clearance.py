"""The page draws the cell's declared solids and marks each run's move with the least clearance."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from codegen.model.cell import DEMO_CELL, load_cell
from codegen.verify import clearance
from codegen.view.page import cell_data
from codegen.view.runs import nominal_runs


def test_solids_drawn_and_the_nearest_move_marked(tmp_path):
    text = Path(DEMO_CELL).read_text(encoding="utf-8")
    cell_file = tmp_path / "cell.toml"
    cell_file.write_text(
        text.replace(
            "[cell.world]",
            "[cell.world]\nsolids.fence = { box = [40, 2000, 1800], pose = [-1500, 0, 900, 0, 0, 0] }\n"
            "solids.column = { cylinder = [100, 2000], pose = [0, 1500, 1000, 0, 0, 0] }",
            1,
        ),
        encoding="utf-8",
    )
    for name in Path(DEMO_CELL).parent.glob("agv_*.csv"):
        (tmp_path / name.name).write_text(name.read_text(encoding="utf-8"), encoding="utf-8")
    cell = load_cell(cell_file)
    data = cell_data(cell, ["ur"])
    solids = {o["label"]: o for o in data["objects"] if o["role"] == "solid"}
    assert solids["fence"]["type"] == "box" and solids["fence"]["size"] == [40.0, 2000.0, 1800.0]
    assert solids["column"]["type"] == "cylinder" and solids["column"]["radius"] == 100.0
    assert np.reshape(solids["column"]["pose"], (4, 4))[:3, 3].tolist() == [0.0, 1500.0, 1000.0]
    program = data["views"][0]["programs"][0]
    entry = nominal_runs(cell, "ur")[0]
    check = clearance.for_program(cell, "ur", program["file"])
    scene = check.scenes[False]
    for run, shown in zip(entry.runs, program["runs"], strict=True):
        mark = shown["clearance"]
        assert 0 <= mark["move"] < len(shown["moves"]) and mark["clearance"] == 20.0
        # the least over every move's whole path is at most what any move's end keeps (measured here, every pair)
        ends = [scene.nearest_at(np.asarray(m.joints)).distance for m in run.trace.moves if m.joints is not None]
        assert 0 < mark["distance"] <= round(min(ends), 1)
