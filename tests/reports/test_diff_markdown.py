"""`codegen diff --format markdown`: a changed cell's programs on disk against its fresh ones, said per program."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.verify import engine
from codegen.verify.engine import Options, verify_cell
from tests.support.cells import MINIMAL_CELL

STATION_3 = """
[[station]]
id = 3
name = "gate"
mark = [640.0, 210.0, 0.0]
[station.poses]
vise = [700.0, 50.0, 260.0, -90.0, 15.0, 180.0]
"""
PROGRAMS = {"ur": "bench.script", "kuka": "bench.src", "abb": "bench.mod", "dtrans": "bench.prg"}


def setup(tmp_path: Path, edit) -> tuple[Path, Path]:
    """A small cell's programs generated under tmp_path/out (the old side), then the cell file edited."""
    cell = tmp_path / "bench.toml"
    cell.write_text(MINIMAL_CELL, encoding="utf-8")
    made = CliRunner().invoke(main, ["generate", str(cell), "--out", str(tmp_path / "out")])
    assert made.exit_code == 0, made.output
    cell.write_text(edit(MINIMAL_CELL), encoding="utf-8")
    return cell, tmp_path / "out"


def invoke(cell: Path, out: Path, *extra):
    return CliRunner().invoke(main, ["diff", str(cell), "--out", str(out), "--format", "markdown", *extra])


def section(markdown: str, target: str, program: str) -> str:
    start = markdown.index(f"##### {target}: `{program}`")
    end = markdown.find("##### ", start + 1)
    return markdown[start : end if end > 0 else len(markdown)]


def test_a_moved_pose_and_an_added_station_are_said_per_program(tmp_path):
    def edit(text):
        return text.replace("chuck = [700.0, -100.0, 300.0,", "chuck = [701.0, -100.0, 300.0,") + STATION_3

    cell, out = setup(tmp_path, edit)
    result = invoke(cell, out, "--no-verify")
    assert result.exit_code == 1, result.output
    text = result.output
    for target, program in PROGRAMS.items():
        assert re.search(rf"^\| {target} \| `{program}` \| changed \| [1-9]", text, re.M), target
        part = section(text, target, program)
        moved = re.findall(r"move (\d+) \(line (\d+)\) in [^:]*station 1 [^:]*: ([\d.]+) mm, ([\d.]+) deg", part)
        assert moved, part
        for _, _line, mm, deg in moved:
            assert float(mm) == pytest.approx(1.0, abs=1e-3) and float(deg) < 1e-3
        # station 3 is new: the old program does not know it and stops before it moves, the new one serves it
        stations = part[part.index("- stations added or removed:") : part.index("- poses moved:")]
        assert re.search(r"station 3 [^\n]*: added \(the old program stops before it moves there", stations)
        assert "stops:" not in part, part
        assert re.search(rf"^\| {target} \| `{program}` \| changed \| 1 \| [1-9]", text, re.M), target
        assert "<details><summary>raw diff" in part and f"+++ {out}" in part


def test_a_removed_station_is_said_per_program(tmp_path):
    """Station 2 taken out of the cell: the old program still serves its id, the new one stops there."""
    cell, out = setup(tmp_path, lambda text: text[: text.index("[[station]]\nid = 2")])
    result = invoke(cell, out, "--no-verify")
    assert result.exit_code == 1, result.output
    for target, program in PROGRAMS.items():
        part = section(result.output, target, program)
        (said,) = re.findall(r"  - removed \(the old program serves it, the new one stops\): (.*)", part)
        assert said.startswith("unknown station id 2: "), said
        assert re.search(rf"^\| {target} \| `{program}` \| changed \| 1 \|", result.output, re.M), target


def test_a_task_of_several_modules_names_the_module_of_each_move(tmp_path):
    """An ABB pallet task (its main module, the pallet's module, the counters' system module): a moved pick pose's
    moves are named at their lines in the pallet's module, and the files that changed are listed."""
    from codegen.model.cell import EXAMPLE_PLANT

    cell = tmp_path / "carton.toml"
    text = (EXAMPLE_PLANT / "pallets" / "carton_abb.toml").read_text(encoding="utf-8")
    cell.write_text(text, encoding="utf-8")
    made = CliRunner().invoke(main, ["generate", str(cell), "--out", str(tmp_path / "out")])
    assert made.exit_code == 0, made.output
    cell.write_text(text.replace("pick = [600.0, ", "pick = [601.0, ", 1), encoding="utf-8")
    result = invoke(cell, tmp_path / "out", "--no-verify")
    assert result.exit_code == 1, result.output
    part = section(result.output, "abb", "pallet_main.mod")
    assert "files changed: `pallet_main.mod`, `pal_carton.mod`" in part.splitlines()[0]
    moved = re.findall(r"move \d+ \((\S+) line (\d+)\) in [^:]*: 1\.000 mm", part)
    assert moved and {name for name, _ in moved} == {"pal_carton.mod"}, part
    module = (tmp_path / "out" / "carton_abb" / "abb" / "pal_carton.mod").read_text().splitlines()
    assert all(re.match(r"\s*(MoveL|MoveJ|MoveAbsJ) ", module[int(line) - 1]) for _, line in moved)


def fast(model, files=(), targets=(), options=None):
    """verify of the new programs with few cases (the verdict's words are the test, not verify's)."""
    return verify_cell(model, files, targets, Options(cases=1, jobs=1, sweeps=False, scenarios=frozenset({"random"})))


def test_a_speed_and_a_zone_are_said_as_settings_with_the_new_programs_verdict(tmp_path, monkeypatch):
    monkeypatch.setattr(engine, "verify_cell", fast)

    def edit(text):  # the defaults: 50 mm/s into the work pose; the zone here a new setting
        return text.replace("[[station]]", "[cell.motion]\nwork_speed_mm_s = 40.0\nzone_mm = 5.0\n\n[[station]]", 1)

    cell, out = setup(tmp_path, edit)
    result = invoke(cell, out)
    assert re.search(r"^\| abb \| `bench.mod` \| changed \|.*\| pass: \d+ cases \|$", result.output, re.M)
    assert "verify of the new programs: all 5 programs match the reference" in result.output
    part = section(result.output, "abb", "bench.mod")
    settings = part[part.index("- speeds, zones, tools:") :]
    assert "40" in settings and "50" in settings and "poses moved" not in part


def test_unchanged_programs_are_said_as_generated_with_the_verdict(tmp_path, monkeypatch):
    monkeypatch.setattr(engine, "verify_cell", fast)
    cell, out = setup(tmp_path, lambda text: text)
    result = invoke(cell, out)
    assert result.exit_code == 0, result.output
    assert "`bench`: programs as generated; verify: all 5 programs match the reference" in result.output


def test_a_change_no_nominal_run_shows_is_listed_as_other(tmp_path):
    cell, out = setup(tmp_path, lambda text: text)
    path = out / "bench" / "abb" / "bench.mod"
    path.write_text(path.read_text().replace("MODULE bench", "MODULE bench\n  ! a note", 1))
    result = invoke(cell, out, "--no-verify")
    assert result.exit_code == 1
    part = section(result.output, "abb", "bench.mod")
    assert "- other changes:" in part and "change nothing in" in part
