"""`codegen run` and `codegen verify` from the command line."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.kinds.station.section import stations_of
from codegen.model.cell import DEMO_CELL, load_cell

REPO = Path(__file__).resolve().parents[2]
GENERATED = REPO / "generated" / "agv_machine_tending"


def invoke(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def test_run_prints_moves_and_log():
    result = invoke(
        "run",
        GENERATED / "kuka" / "agv_machine_tending.src",
        "--input",
        "VIS_STATION=3",
        "--input",
        "VIS_X=642.2",
        "--input",
        "VIS_Y=209.1",
        "--input",
        "VIS_THETA=3.1",
    )
    assert result.exit_code == 0, result.output
    assert result.output.count("message: deviation") == 2
    assert "joint " in result.output and "linear " in result.output


def test_run_json_and_halt():
    path = GENERATED / "abb" / "agv_machine_tending.mod"
    result = invoke("run", path, "--input", "vis_station=42", "--start", "0,0,0,0,90,30", "--json")
    data = json.loads(result.output)
    assert data["halted"] is True and data["halt_message"] == "unknown station id 42"
    (home,) = data["moves"]  # only the home move: without --robot known by its joints alone
    assert home["joints"] == [0, 0, 0, 0, 90, 30] and home["pose"] is None  # the demo's home (axis 6 at 30)


def test_run_with_the_arm_solves_every_move():
    path = GENERATED / "kuka" / "agv_machine_tending.src"
    reading = ["--input", "VIS_STATION=1", "--input", "VIS_X=612.4", "--input", "VIS_Y=-285"]
    reading += ["--input", "VIS_THETA=1.8"]
    result = invoke("run", path, *reading, "--gripper", "$OUT[17]=$IN[18]", "--robot", "KR 10 R1100 sixx", "--json")
    data = json.loads(result.output)
    # home, station 1's taught poses (the first a joint move), its retreat, home
    taught = len(stations_of(load_cell(DEMO_CELL))[0].poses)
    assert [m["motion"] for m in data["moves"]] == ["joint", "joint"] + ["linear"] * taught + ["joint"]
    assert all(m["joints"] is not None and m["pose"] is not None for m in data["moves"])
    assert data["moves"][0]["joints"] == [0, -90, 90, 0, 90, 30]  # the demo's home (axis 6 at 30)
    wrong = invoke("run", path, "--robot", "IRB 140")
    assert wrong.exit_code == 2 and "an arm of the abb controller; this program is for kuka" in wrong.output
    unknown = invoke("run", path, "--robot", "KR 1")
    assert unknown.exit_code == 2 and "not in the catalogue" in unknown.output


def test_run_reports_syntax_errors_with_position(tmp_path):
    broken = tmp_path / "broken.script"
    broken.write_text("def x():\n  if 1 > 0\n  end\nend\n")
    result = invoke("run", broken)
    assert result.exit_code == 2
    assert "broken.script:2:" in result.output and "syntax error" in result.output


@pytest.mark.slow
def test_verify_fresh_output_json():
    result = invoke("verify", "--cases", "5", "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.output)
    assert data["ok"] is True
    assert [t["target"] for t in data["targets"]] == ["ur", "ur", "kuka", "abb", "dtrans"]  # UR: socket and node
    assert [t["program"] for t in data["targets"][:2]] == ["agv_machine_tending", "agv_machine_tending_node"]
    for t in data["targets"]:
        assert t["mismatches"] == 0 and t["cases"] > 100
        assert t["categories"]["unknown_station"] >= 4 and t["categories"]["invalid_reading"] >= 8
        assert t["position_error_mm"]["max"] <= 0.005


def test_verify_catches_a_hand_edited_file(tmp_path, no_sweeps):
    source = (GENERATED / "ur" / "agv_machine_tending.script").read_text()
    edited = tmp_path / "edited.script"
    edited.write_text(source.replace("  if dx * dx + dy * dy > MAX_SHIFT_SQ:", "  if dx * dx > MAX_SHIFT_SQ:"))
    result = invoke("verify", edited, "--cases", "5")
    assert result.exit_code == 1
    assert "MISMATCH" in result.output and "expected a stop ('station " in result.output
    assert "mark shift over 10 mm" in result.output


def test_verify_files_on_disk_pass(no_sweeps):
    files = [GENERATED / "kuka" / "agv_machine_tending.src", GENERATED / "dtrans" / "agv_machine_tending.prg"]
    result = invoke("verify", *files, "--cases", "5")
    assert result.exit_code == 0, result.output
    assert "kuka" in result.output and "dtrans" in result.output


def test_verify_refuses_to_verify_nothing():
    result = invoke("verify", GENERATED / "kuka" / "agv_machine_tending.dat", "--cases", "2")
    assert result.exit_code == 2 and "a data list is read with its program" in result.output


def test_verify_warns_when_the_file_comes_from_another_cell():
    bench = REPO / "generated" / "thermometer_bench" / "dtrans" / "thermometer_bench.prg"
    proc = subprocess.run(
        [sys.executable, "-m", "codegen", "verify", str(bench), "--cases", "2"], capture_output=True, text=True
    )
    assert "generated from another cell file" in proc.stderr
    assert proc.returncode == 1  # the demo cell's readings do not fit the bench program


def test_a_runaway_program_stops_verify_at_its_first_runaway_case(tmp_path, no_sweeps):
    """An endless loop in one station: verify reports it once per chunk of cases (a worker's share; station
    1 is in the first chunk and the start_retreat case in the last) and runs no more cases of that chunk (it
    ran every case to the step limit before, for minutes); --step-limit sets the limit."""
    from pathlib import Path

    generated = Path(__file__).resolve().parents[2] / "generated" / "agv_machine_tending" / "ur"
    text = (generated / "agv_machine_tending.script").read_text()
    looped = text.replace("  def st_lathe_1():\n", "  def st_lathe_1():\n    while True:\n      sync()\n    end\n", 1)
    assert looped != text
    path = tmp_path / "agv_machine_tending.script"
    path.write_text(looped)
    demo = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "agv_machine_tending.toml"
    result = CliRunner().invoke(
        main, ["verify", str(demo), str(path), "--cases", "50", "--jobs", "1", "--step-limit", "5000", "--json"]
    )
    assert result.exit_code == 1
    report = json.loads(result.output)["targets"][0]
    assert report["mismatches"] == 2 and all("step limit 5000 reached" in m for m in report["first_mismatches"])
    from codegen.kinds.station.cases import build_cases
    from codegen.model.cell import load_cell

    assert report["cases"] < len(build_cases(load_cell(demo), 50, 0))  # the chunk with station 1 stopped


def _socket_and_node(tmp_path: Path, broken: str) -> list[Path]:
    """The demo's UR socket program and its Script-node twin, copied; `broken` gets sin and cos swapped."""
    tmp_path.mkdir(parents=True, exist_ok=True)
    out = []
    for name in ("agv_machine_tending.script", "agv_machine_tending_node.script"):
        text = (GENERATED / "ur" / name).read_text(encoding="utf-8")
        if name == broken:
            assert "sin_phi = sin(phi)" in text
            text = text.replace("sin_phi = sin(phi)", "sin_phi = cos(phi)")
        path = tmp_path / name
        path.write_text(text, encoding="utf-8")
        out.append(path)
    return out


def test_two_programs_of_one_target_are_two_rows_each_run(tmp_path):
    """Each file given is run on its own: the broken one fails beside its untouched twin, either way round."""
    from codegen.kinds.station.cases import build_cases
    from codegen.verify.engine import Options, verify_sources
    from codegen.verify.programs import file_sources

    cell = load_cell(DEMO_CELL)
    cases = build_cases(cell, 3, 1)
    for broken in ("agv_machine_tending.script", "agv_machine_tending_node.script"):
        paths = _socket_and_node(tmp_path / broken, broken)
        for order in (paths, paths[::-1]):
            sources, _warnings = file_sources(cell, order, ("ur",))
            # the sin/cos swap shows in the positions: no trace swept against the cell's solids (its own tests)
            options = Options(cases=3, seed=1, jobs=1, sweeps=False, clearance=False)
            reports, _ = verify_sources(cell, sources, options)
            assert [Path(r.files[0]).name for r in reports] == [p.name for p in order]
            for path, report in zip(order, reports, strict=True):
                assert report.cases == len(cases)
                assert (report.mismatches > 0) == (path.name == broken), (path.name, report.first_mismatches)


@pytest.mark.slow  # a whole verify run: in the slow set (the default run stays near 5 minutes)
def test_verify_reports_a_row_per_file(tmp_path):
    paths = _socket_and_node(tmp_path, "agv_machine_tending_node.script")
    result = invoke("verify", *paths, "--target", "ur", "--cases", "1", "--jobs", "1", "--json")
    assert result.exit_code == 1, result.output
    rows = json.loads(result.output)["targets"]
    assert [(Path(r["files"][0]).name, r["mismatches"] > 0) for r in rows] == [
        ("agv_machine_tending.script", False),
        ("agv_machine_tending_node.script", True),
    ]
