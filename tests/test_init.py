"""`codegen init KIND [--target T]...`: a commented starter cell of each kind, for the targets asked, that loads and
generates as written; an existing file is never replaced."""

from __future__ import annotations

import tomllib

import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.model.cell import load_cell
from codegen.protocol import installed_kinds


def init(tmp_path, *args):
    return CliRunner().invoke(main, ["init", *args], catch_exceptions=False)


@pytest.mark.parametrize("kind", sorted(installed_kinds()))
def test_each_kind_has_a_commented_starter_that_loads(tmp_path, kind):
    out = tmp_path / f"{kind}.toml"
    result = init(tmp_path, kind, "--out", str(out))
    assert result.exit_code == 0, result.output
    text = out.read_text(encoding="utf-8")
    assert text.lstrip().startswith("#")  # commented
    cell = load_cell(out)
    assert kind in cell.kinds


def test_a_starter_for_one_target_names_no_other(tmp_path):
    out = tmp_path / "pallet.toml"
    assert init(tmp_path, "pallet", "--target", "kuka", "--out", str(out)).exit_code == 0
    text = out.read_text(encoding="utf-8")
    data = tomllib.loads(text)
    assert data["cell"]["targets"] == ["kuka"]
    assert set(data["cell"]["robot"]) == {"kuka"}
    assert data["cell"]["io"]["output"] == {"kuka": 17}
    assert "pallet_present" in data["pallet"][0]["io"]
    assert load_cell(out).targets == ("kuka",)


def test_a_starter_for_one_target_keeps_its_comments_in_their_column(tmp_path):
    """The [pallet.io] lines lose their other targets' items; their comments stay in line with one another."""
    out = tmp_path / "pallet.toml"
    assert init(tmp_path, "pallet", "--target", "kuka", "--out", str(out)).exit_code == 0
    lines = out.read_text(encoding="utf-8").splitlines()
    start = next(i for i, x in enumerate(lines) if x.startswith("[pallet.io]"))
    shortened = [x for x in lines[start + 1 :] if x.startswith(("part_present", "pallet_present", "reset", "done"))]
    assert len(shortened) >= 4
    assert len({x.index("#") for x in shortened}) == 1, shortened


def test_an_existing_file_stays_and_a_target_the_starter_lacks_is_named(tmp_path):
    out = tmp_path / "mine.toml"
    out.write_text("# my cell\n", encoding="utf-8")
    result = init(tmp_path, "laser", "--out", str(out))
    assert result.exit_code == 2
    assert "the file exists" in result.output
    assert out.read_text(encoding="utf-8") == "# my cell\n"
    missing = init(tmp_path, "laser", "--target", "dtrans", "--out", str(tmp_path / "l.toml"))
    assert missing.exit_code == 2
    assert "--target dtrans: the starter is written for ur, kuka, abb" in missing.output
    assert not (tmp_path / "l.toml").exists()
    unknown = init(tmp_path, "weld")
    assert unknown.exit_code == 2
    assert "weld: not a program kind" in unknown.output


@pytest.mark.parametrize("mode", ["point", "frame"])
def test_a_station_mode_is_an_init_kind_with_its_stations_alone(tmp_path, mode):
    out = tmp_path / f"{mode}.toml"
    result = init(tmp_path, mode, "--out", str(out))
    assert result.exit_code == 0, result.output
    text = out.read_text(encoding="utf-8")
    assert text.lstrip().startswith("#")
    cell = load_cell(out)
    stations = cell.sections["station"].stations
    assert stations and {s.mode for s in stations} == {mode}
    data = tomllib.loads(text)
    assert ("refine" in data["cell"]) is (mode == "frame")  # the other mode's [cell.<table>] goes with its stations
    assert ("handeye" in data["cell"]["camera"]) is (mode == "frame")
    assert data["cell"]["name"].endswith(f"_{mode}")  # init point and init frame in one folder: two files
    generated = CliRunner().invoke(main, ["generate", str(out), "--out", str(tmp_path / "gen")])
    assert generated.exit_code == 0, generated.output
    for target in cell.targets:
        assert any((tmp_path / "gen" / cell.name / target).iterdir())


def test_a_mode_starter_for_one_target(tmp_path):
    out = tmp_path / "frame.toml"
    assert init(tmp_path, "frame", "--target", "abb", "--out", str(out)).exit_code == 0
    cell = load_cell(out)
    assert cell.targets == ("abb",) and {s.mode for s in cell.sections["station"].stations} == {"frame"}


@pytest.mark.slow
@pytest.mark.parametrize("mode", ["point", "frame"])
def test_a_mode_starter_generates_and_verifies_as_written(tmp_path, mode):
    out = tmp_path / f"{mode}.toml"
    assert init(tmp_path, mode, "--out", str(out)).exit_code == 0
    assert CliRunner().invoke(main, ["generate", str(out), "--out", str(tmp_path / "gen")]).exit_code == 0
    verified = CliRunner().invoke(main, ["verify", str(out), "--cases", "5", "--jobs", "1"])
    assert verified.exit_code == 0, verified.output
    assert "verify: all traces match the reference" in verified.output
