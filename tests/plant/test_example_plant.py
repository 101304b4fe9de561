"""The example plant: at least twelve distinct cells over every kind and controller, its committed programs fresh,
and (slow) verified whole, then every cell cached."""

from __future__ import annotations

import json
import shutil
import tomllib
from pathlib import Path

import jsonschema
import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.controllers import target_names
from codegen.generate import diff
from codegen.kinds.station.mode import modes
from codegen.kinds.station.section import stations_of
from codegen.model.cell import EXAMPLE_PLANT, EXAMPLES_DIR, load_cell
from codegen.plant.config import load_plant
from codegen.protocol import installed_kinds

CELLS = load_plant(EXAMPLE_PLANT).cells


def test_the_example_plant_has_a_dozen_distinct_cells_of_every_kind_and_controller():
    cells = [load_cell(path) for path in CELLS]
    assert len(cells) >= 12
    assert len({c.name for c in cells}) == len(cells) and len({c.sha256 for c in cells}) == len(cells)
    assert {t for c in cells for t in c.targets} == set(target_names())
    assert {k for c in cells for k in c.sections} == set(installed_kinds())
    assert {s.mode for c in cells for s in stations_of(c)} == set(modes())


@pytest.mark.parametrize("path", CELLS, ids=lambda p: p.relative_to(EXAMPLE_PLANT).as_posix())
def test_the_example_plants_cells_follow_the_schema_and_their_programs_are_fresh(path: Path):
    schema = json.loads((EXAMPLES_DIR / "cell.schema.json").read_text())
    jsonschema.validate(tomllib.loads(path.read_text()), schema)
    text = diff(load_cell(path), EXAMPLE_PLANT / "generated")
    assert text == "", "run `codegen generate codegen/examples/plant` and commit:\n" + text[:2000]


@pytest.mark.slow
def test_the_example_plant_verifies_then_every_cell_is_cached(tmp_path: Path):
    plant = tmp_path / "plant"
    shutil.copytree(EXAMPLE_PLANT, plant, ignore=shutil.ignore_patterns("generated"))
    first = CliRunner().invoke(main, ["verify", str(plant), "--json"])
    report = json.loads(first.output)
    assert first.exit_code == 0 and {row["result"] for row in report["rows"]} == {"ok"}
    assert len(report["rows"]) == len(CELLS)
    second = json.loads(CliRunner().invoke(main, ["verify", str(plant), "--json"]).output)
    assert {row["result"] for row in second["rows"]} == {"cached"}
