"""generate, diff and check of a plant: every cell, one table, a bad cell a row of its own, nothing half-written."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from codegen.cli import main


def _run(*args: str):
    result = CliRunner().invoke(main, [*args, "--json"])
    return result.exit_code, json.loads(result.output)


def _results(report: dict) -> dict[str, str]:
    return {f"{row['cell']} {row['target']}": row["result"] for row in report["rows"]}


def test_generate_then_diff_then_an_edit_then_check(plant: Path):
    code, report = _run("generate", str(plant))
    assert code == 0 and _results(report) == {"a/tray.toml dtrans": "written", "b/gate.toml dtrans": "written"}
    out = plant / "generated"
    assert sorted(p.name for p in out.iterdir() if p.is_dir()) == ["tray_dtrans", "warehouse_dtrans"]
    code, report = _run("diff", str(plant))
    assert code == 0 and set(_results(report).values()) == {"ok"}
    program = next((out / "warehouse_dtrans" / "dtrans").glob("*.prg"))
    program.write_text(program.read_text().replace("\n", "\n; edited\n", 1))
    code, report = _run("diff", str(plant))
    assert code == 1 and _results(report) == {"a/tray.toml dtrans": "ok", "b/gate.toml dtrans": "differs"}
    assert "; edited" in report["cells"][1]["data"]["diff"]
    code, report = _run("check", str(plant))
    rows = _results(report)  # the edit is no Decompose/Trans statement: that program does not parse
    assert code == 2 and rows["a/tray.toml dtrans"] in ("clean", "findings") and rows["b/gate.toml dtrans"] == "error"
    assert program.name in report["rows"][1]["message"]


def test_a_bad_cell_among_good_ones_is_reported_and_the_others_are_written(plant: Path):
    (plant / "bad.toml").write_text('[cell]\nname = "bad"\ntargets = ["ur"]\npose_format = "nonsense"\n')
    code, report = _run("generate", str(plant))
    assert code == 2
    assert _results(report) == {"a/tray.toml dtrans": "written", "b/gate.toml dtrans": "written", "bad.toml *": "error"}
    assert "pose_format" in next(r["message"] for r in report["rows"] if r["cell"] == "bad.toml")
    assert not (plant / "generated" / "bad").exists()


def test_check_of_a_plant_without_programs_says_how_to_make_them(plant: Path):
    code, report = _run("check", str(plant))
    assert code == 2 and set(_results(report).values()) == {"error"}
    assert all("codegen generate" in row["message"] for row in report["rows"])


def test_the_plants_out_folder_and_targets(plant: Path):
    (plant / "codegen.toml").write_text('[plant]\nout = "programs"\ntargets = ["dtrans", "ur"]\n')
    code, report = _run("generate", str(plant))
    assert code == 0 and (plant / "programs" / "tray_dtrans" / "dtrans").is_dir()
    (plant / "codegen.toml").write_text('[plant]\ntargets = ["ur"]\n')
    code, report = _run("generate", str(plant))
    assert code == 0 and set(_results(report).values()) == {"skipped"}
