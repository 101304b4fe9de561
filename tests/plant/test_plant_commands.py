"""generate, diff and check of a plant: every cell, one table, a bad cell a row of its own, nothing half-written."""

from __future__ import annotations

import json
import shutil
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


def test_a_module_loaded_into_the_production_task_is_checked_from_its_entry(tmp_path: Path):
    """The ABB laser module has no PROC main by design (the production task's main calls its routine): a plant's
    check starts it at the routine its plan names, and so does `codegen check --entry`; a wrong routine is an error,
    a language without entry routines refuses the option."""
    from codegen.model.cell import EXAMPLES_DIR

    repo = Path(__file__).resolve().parents[2]
    plant = tmp_path / "plant"
    shutil.copytree(repo / "generated" / "laser_tcp", plant / "generated" / "laser_tcp")
    shutil.copyfile(EXAMPLES_DIR / "laser" / "laser_tcp.toml", plant / "laser_tcp.toml")
    (plant / "codegen.toml").write_text('[plant]\ntargets = ["abb"]\n')
    code, report = _run("check", str(plant))
    assert code == 0 and _results(report) == {"laser_tcp.toml abb": "clean"}, report
    folder = str(plant / "generated" / "laser_tcp" / "abb")
    runner = CliRunner()
    alone = runner.invoke(main, ["check", folder])
    assert alone.exit_code == 1 and "[no-main]" in alone.output
    assert runner.invoke(main, ["check", folder, "--entry", "tcp_laser_tcp_run"]).exit_code == 0
    wrong = runner.invoke(main, ["check", folder, "--entry", "main_nope"])
    assert wrong.exit_code == 2 and "no global PROC main_nope" in wrong.output
    refused = runner.invoke(main, ["check", str(plant / "generated" / "laser_tcp" / "ur"), "--entry", "x"])
    assert refused.exit_code == 2 and "--entry x: a ur program starts only at its own entry" in refused.output


def test_a_plants_generate_prints_each_cells_home_and_pose_margins_as_the_cells_own_generate(tmp_path: Path):
    from codegen.model.cell import EXAMPLE_PLANT

    plant = tmp_path / "plant"
    plant.mkdir()
    shutil.copyfile(EXAMPLE_PLANT / "lasers" / "pin_kuka.toml", plant / "pin.toml")
    alone = CliRunner().invoke(main, ["generate", str(plant / "pin.toml"), "--out", str(tmp_path / "alone")])
    assert alone.exit_code == 0, alone.output
    margins = [line for line in alone.output.splitlines() if not line.startswith("wrote ")]
    assert margins and margins[0].startswith("home kuka (KR 10 R1100 sixx): ")
    together = CliRunner().invoke(main, ["generate", str(plant)])
    assert together.exit_code == 0, together.output
    lines = together.output.splitlines()
    row = next(i for i, line in enumerate(lines) if line.startswith("pin.toml "))
    assert [line.strip() for line in lines[row + 1 : row + 1 + len(margins)]] == [m.strip() for m in margins]
    code, report = _run("generate", str(plant), "--out", str(tmp_path / "again"))
    assert code == 0 and report["cells"][0]["data"]["home"][0]["target"] == "kuka"
