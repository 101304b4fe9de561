"""`codegen diff PLANT --format markdown`: one document over the plant's changed cells, the unchanged ones counted,
a cell that cannot be diffed named with its message and the others done."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.verify import engine
from codegen.verify.engine import Options, verify_cell

SHELF = "shelf = [-62.0, -902.5,"  # a pose of station 7 of the gate cell (tests/plant/conftest.py's b/gate.toml)


@pytest.fixture
def generated(plant: Path) -> Path:
    """The plant's programs generated (the old side), then one pose of the gate cell moved 1 mm in x."""
    made = CliRunner().invoke(main, ["generate", str(plant)])
    assert made.exit_code == 0, made.output
    gate = plant / "b" / "gate.toml"
    text = gate.read_text(encoding="utf-8")
    assert SHELF in text
    gate.write_text(text.replace(SHELF, "shelf = [-61.0, -902.5,"), encoding="utf-8")
    return plant


def _diff(plant: Path, *extra: str):
    return CliRunner().invoke(main, ["diff", str(plant), "--format", "markdown", *extra])


def test_the_changed_cell_and_program_are_said_and_the_unchanged_cell_counted(generated: Path):
    result = _diff(generated, "--no-verify")
    assert result.exit_code == 1, result.output
    text = result.output
    assert text.startswith("### codegen diff of plant ") and ": 1 of 2 cells changed" in text.splitlines()[0]
    assert "1 cell unchanged" in text
    assert "#### `warehouse_dtrans` (b/gate.toml)" in text
    assert re.search(r"^\| dtrans \| `warehouse_dtrans.prg` \| changed \| +\| [1-9]", text, re.M), text
    moved = re.findall(r"move \d+ \(line \d+\) in [^:]*station 7 [^:]*: ([\d.]+) mm, ([\d.]+) deg", text)
    assert moved and all(float(mm) == pytest.approx(1.0, abs=1e-3) and float(deg) < 1e-3 for mm, deg in moved)
    assert "<details><summary>raw diff" in text and "+Point p7_shelf = Trans(-61.0000" in text
    assert "tray" not in text  # the unchanged cell is not listed
    assert "verify of the new programs" not in text and "pass:" not in text  # --no-verify


def test_nothing_changed_is_exit_0(plant: Path):
    assert CliRunner().invoke(main, ["generate", str(plant)]).exit_code == 0
    result = _diff(plant, "--no-verify")
    assert result.exit_code == 0, result.output
    assert ": 0 of 2 cells changed" in result.output and "2 cells unchanged" in result.output


def test_a_broken_cell_is_named_with_its_message_and_the_others_are_done(generated: Path):
    (generated / "c.toml").write_text('[cell\nname = "broken"\n', encoding="utf-8")
    result = _diff(generated, "--no-verify")
    assert result.exit_code == 2, result.output
    text = result.output
    assert ": 1 of 3 cells changed" in text.splitlines()[0] and "1 cell unchanged" in text
    (said,) = re.findall(r"^- `c\.toml`: (.*)$", text, re.M)
    assert "c.toml" in said and "line 1" in said, said
    assert "#### `warehouse_dtrans` (b/gate.toml)" in text and "station 7" in text


def test_the_changed_cells_new_programs_alone_are_verified_with_the_plants_options(generated: Path, monkeypatch):
    (generated / "codegen.toml").write_text("[plant]\ncases = 1\nseed = 7\n", encoding="utf-8")
    verified = []

    def fast(model, files=(), targets=(), options=None):
        """verify of the new programs with few cases (the verdict's words are the test, not verify's)."""
        verified.append((model.name, options.cases, options.seed))
        few = Options(cases=1, seed=options.seed, jobs=1, sweeps=False, scenarios=frozenset({"random"}))
        return verify_cell(model, files, targets, few)

    monkeypatch.setattr(engine, "verify_cell", fast)
    result = _diff(generated)
    assert result.exit_code == 1, result.output
    assert verified == [("warehouse_dtrans", 1, 7)]
    assert "verify of the new programs: all 1 programs match the reference" in result.output
    assert ", seed 7)" in result.output
    assert re.search(r"^\| dtrans \| `warehouse_dtrans.prg` \| changed \|.*\| pass: \d+ cases \|$", result.output, re.M)
