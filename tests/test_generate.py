"""generate / diff: committed output is fresh, writes are all-or-nothing, diff reports changes."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from click.testing import CliRunner

from codegen.cell import load_cell
from codegen.cli import main
from codegen.generate import diff, generate
from codegen.render import render

REPO = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("cell_file", sorted(p.name for p in (REPO / "codegen" / "examples").glob("*.toml")))
def test_committed_generated_output_is_fresh(cell_file):
    """Fails when generated/ is stale: run `codegen generate CELL` for every example cell and commit the result."""
    text = diff(load_cell(REPO / "codegen" / "examples" / cell_file), REPO / "generated")
    assert text == "", "generated/ is stale; run `codegen generate`:\n" + text[:3000]


def test_generate_then_diff_is_clean(tmp_path):
    runner = CliRunner()
    result = runner.invoke(main, ["generate", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    written = sorted(p.relative_to(tmp_path).as_posix() for p in tmp_path.rglob("*") if p.is_file())
    assert len(written) == 6 and ".agv_machine_tending.lock" in written  # 5 programs and the cell's lock
    demo = str(REPO / "codegen" / "examples" / "agv_machine_tending.toml")
    assert runner.invoke(main, ["diff", demo, "--out", str(tmp_path)]).exit_code == 0


def test_diff_reports_an_edit_and_an_extra_file(tmp_path):
    cell = load_cell()
    generate(cell, None, tmp_path)
    script = next(tmp_path.rglob("*.script"))
    script.write_text(script.read_text().replace("612.400000", "612.500000"))
    (script.parent / "old_name.script").write_text("def x():\nend\n")
    result = CliRunner().invoke(main, ["diff", "--out", str(tmp_path)])
    assert result.exit_code == 1
    assert "-  m1_lathe_1 = [612.500000" in result.output
    assert "+  m1_lathe_1 = [612.400000" in result.output
    assert "Only in" in result.output and "old_name.script" in result.output
    generate(cell, None, tmp_path)
    assert not (script.parent / "old_name.script").exists()


def _snapshot(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def test_emit_error_leaves_previous_output_intact(tmp_path):
    generate(load_cell(), None, tmp_path)
    before = _snapshot(tmp_path)
    bad = tmp_path / "bad.toml"
    text = (REPO / "codegen/examples/agv_machine_tending.toml").read_text()
    bad.write_text(text.replace('name = "lathe_2"', 'name = "lathe-1"'))  # maps onto lathe_1
    result = CliRunner().invoke(main, ["generate", str(bad), "--out", str(tmp_path)])
    assert result.exit_code == 2
    assert "both map to the identifier" in result.output
    assert _snapshot(tmp_path) == {k: v for k, v in before.items()} | {"bad.toml": bad.read_bytes()}


def test_write_failure_midway_leaves_previous_output_intact(tmp_path, monkeypatch):
    cell = load_cell()
    generate(cell, None, tmp_path)
    before = _snapshot(tmp_path)
    changed = cell.__class__(**{**cell.__dict__, "sha256": "0" * 64})
    calls = {"n": 0}
    real_fsync = os.fsync

    def failing_fsync(fd):
        calls["n"] += 1
        if calls["n"] == 3:
            raise OSError(28, "No space left on device")
        return real_fsync(fd)

    monkeypatch.setattr(os, "fsync", failing_fsync)
    with pytest.raises(OSError):
        generate(changed, None, tmp_path)
    assert _snapshot(tmp_path) == before  # nothing replaced, no temporary files left


def test_generate_refuses_unknown_target():
    result = CliRunner().invoke(main, ["generate", "--target", "fanuc", "--out", "unused"])
    assert result.exit_code == 2
    assert "--target fanuc" in result.output


def test_render_names_follow_the_cell():
    paths = [f.relpath for f in render(load_cell())]
    assert paths == [
        "agv_machine_tending/ur/agv_machine_tending.script",
        "agv_machine_tending/kuka/agv_machine_tending.src",
        "agv_machine_tending/kuka/agv_machine_tending.dat",
        "agv_machine_tending/abb/agv_machine_tending.mod",
        "agv_machine_tending/dtrans/agv_machine_tending.prg",
    ]
