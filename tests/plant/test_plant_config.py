"""A plant's cells: discovery in a folder, the codegen.toml's schema and its errors."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.plant.config import PlantError, load_plant


def _names(plant) -> list[str]:
    return [plant.label(p) for p in plant.cells]


def test_discovery_finds_cells_and_skips_hidden_output_and_other_toml(plant: Path):
    cell = (plant / "a" / "tray.toml").read_bytes()
    for folder in (".hidden", ".venv", "generated", "venv"):
        (plant / folder).mkdir()
        (plant / folder / "copy.toml").write_bytes(cell)
    (plant / "pyproject.toml").write_text('[project]\nname = "x"\n')
    (plant / "c").mkdir()
    (plant / "c" / "typo.toml").write_text("[cell\n")  # may be a cell: listed, its row says what is wrong
    found = load_plant(plant)
    assert _names(found) == ["a/tray.toml", "b/gate.toml", "c/typo.toml"]
    assert found.skipped == ("pyproject.toml",)
    assert found.config is None and found.cases is None


def test_codegen_toml_lists_cells_in_its_order_and_sets_defaults(plant: Path):
    (plant / "codegen.toml").write_text(
        '[plant]\nname = "line 4"\ncells = ["b/gate.toml", "a/*.toml", "b/gate.toml"]\nout = "programs"\n'
        'targets = ["dtrans"]\ncases = 3\nseed = 7\ncache = "store"\n'
    )
    for given in (plant, plant / "codegen.toml"):
        found = load_plant(given)
        assert _names(found) == ["b/gate.toml", "a/tray.toml"]
        assert (found.name, found.cases, found.seed, found.targets) == ("line 4", 3, 7, ("dtrans",))
        assert found.out == plant.resolve() / "programs" and found.cache == plant.resolve() / "store"


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("[plant]\ncase = 3\n", "plant.case: unknown key"),
        ('[plant]\ncases = "3"\n', "plant.cases: expected an integer, got a string"),
        ("[plant]\ncases = true\n", "plant.cases: expected an integer"),
        ("[plant]\ncases = -1\n", "plant.cases: -1 is out of range"),
        ('[plant]\ntargets = ["fanuc"]\n', "plant.targets[0]: 'fanuc' is no controller"),
        ('[plant]\ncells = ["nothing/*.toml"]\n', "plant.cells[0]: 'nothing/*.toml' matches no file"),
        ('[plant]\ncells = ["../x.toml"]\n', "plant.cells[0]: '../x.toml' is outside the plant's folder"),
        ('[plant]\ncells = ["missing.toml"]\n', "plant.cells[0]: 'missing.toml': no such file"),
        ('[plant]\nout = " "\n', "plant.out: empty"),
        ("[cells]\n", "cells: unknown table or key"),
        ("name = 1\n", "name: unknown table or key"),
        ("[plant\n", "TOML syntax error"),
    ],
)
def test_a_bad_codegen_toml_names_file_and_key_and_exits_2(plant: Path, text: str, message: str):
    config = plant / "codegen.toml"
    config.write_text(text)
    with pytest.raises(PlantError, match=None) as caught:
        load_plant(plant)
    assert str(caught.value).startswith(f"{config}: ") and message in str(caught.value)
    result = CliRunner().invoke(main, ["verify", str(plant), "--no-cache"])
    assert result.exit_code == 2 and message in result.output and "Traceback" not in result.output


def test_a_folder_without_cells_is_bad_input(tmp_path: Path):
    result = CliRunner().invoke(main, ["verify", str(tmp_path)])
    assert result.exit_code == 2 and "no cell files here" in result.output
