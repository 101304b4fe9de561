"""A plant's verify and check as JUnit (a suite per cell), SARIF (one run, every cell's findings at repository-relative
files) and GitHub annotations (every cell's): valid against the published schemas, a cell that cannot be done an
error, a cached cell reported as when it ran, wherever the plant now is."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.model.cell import EXAMPLE_PLANT

# a mismatch as verify words one: the move, its pose's key and the program's line
MISMATCH = "random 1: move 2 (shelf, line 7) position error 3.000 mm"
BAD_CELL = '[cell]\nname = "bad"\ntargets = ["ur"]\npose_format = "nonsense"\n'


@pytest.fixture
def repo(plant: Path, monkeypatch) -> Path:
    """The plant inside a repository (a folder holding .git), the current folder its root."""
    root = plant.parent
    (root / ".git").mkdir()
    monkeypatch.chdir(root)
    return root


def _invoke(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, list(args))
    assert "Traceback" not in result.output, result.output
    return result.exit_code, result.output


def test_verify_of_a_plant_as_junit_sarif_and_github(repo, plant, fake_verify, junit_valid, sarif_valid):
    fake_verify.failing, fake_verify.mismatch = {"warehouse_dtrans"}, MISMATCH
    (plant / "c.toml").write_text(BAD_CELL)
    code, text = _invoke("verify", str(plant), "--format", "junit")
    assert code == 2
    suites = junit_valid(text).findall("testsuite")
    assert [s.get("name") for s in suites] == ["verify a/tray.toml", "verify b/gate.toml", "verify c.toml"]
    assert [(s.get("failures"), s.get("errors")) for s in suites] == [("0", "0"), ("1", "0"), ("0", "1")]
    assert suites[1].get("file") == "plant/b/gate.toml"
    assert "pose_format" in suites[2].find("testcase/error").text

    code, text = _invoke("verify", str(plant), "--format", "sarif")  # the good cells from the cache now
    assert code == 2
    (run,) = sarif_valid(text)["runs"]
    places = {r["ruleId"]: r for r in run["results"]}
    assert set(places) == {"verify/pose", "plant/cell"}
    located = places["verify/pose"]["locations"][0]["physicalLocation"]
    assert located["artifactLocation"] == {"uri": "plant/generated/warehouse_dtrans", "uriBaseId": "SRCROOT"}
    assert located["region"] == {"startLine": 7}
    (key,) = places["verify/pose"]["relatedLocations"]
    lines = (plant / "b" / "gate.toml").read_text().splitlines()
    assert key["physicalLocation"]["artifactLocation"]["uri"] == "plant/b/gate.toml"
    assert lines[key["physicalLocation"]["region"]["startLine"] - 1].startswith("shelf = ")
    assert places["plant/cell"]["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] == "plant/c.toml"
    assert [r["properties"]["cell"] for r in run["results"]] == ["b/gate.toml", "c.toml"]

    code, text = _invoke("verify", str(plant), "--format", "github")
    assert code == 2
    annotations = text.splitlines()
    assert len(annotations) == 2
    assert annotations[0].startswith("::error file=plant/generated/warehouse_dtrans,line=7,title=verify/pose (b/gate")
    assert annotations[1].startswith("::error file=plant/c.toml,title=plant/cell (c.toml)::")


def test_a_cached_result_reports_its_findings_where_the_plant_now_is(repo, plant, fake_verify, sarif_valid):
    """The plant and its cache moved to another folder (another checkout): the cached cells' findings name the
    files where they are now."""
    fake_verify.failing, fake_verify.mismatch = {"warehouse_dtrans"}, MISMATCH
    code, first = _invoke("verify", str(plant), "--format", "sarif")
    assert code == 1 and fake_verify.calls == ["tray_dtrans", "warehouse_dtrans"]
    moved = repo / "elsewhere"
    shutil.copytree(plant, moved)
    code, again = _invoke("verify", str(moved), "--format", "sarif")
    assert code == 1 and fake_verify.calls == ["tray_dtrans", "warehouse_dtrans"]  # all from the cache
    assert again == first.replace('"plant/', '"elsewhere/')
    assert '"elsewhere/generated/warehouse_dtrans"' in again
    sarif_valid(again)


def test_check_of_a_plant_as_junit_sarif_and_github(repo, plant, junit_valid, sarif_valid):
    """A hand-edited program of one cell: its finding at the edited line, a suite per cell, the other clean."""
    out = plant / "generated"
    for name in ("tray_dtrans", "nozzle_ur"):
        shutil.copytree(EXAMPLE_PLANT / "generated" / name, out / name)
    shutil.copyfile(EXAMPLE_PLANT / "lasers" / "nozzle_ur.toml", plant / "b" / "nozzle.toml")
    (plant / "b" / "gate.toml").unlink()
    program = out / "nozzle_ur" / "ur" / "tcp_nozzle_ur_node.script"
    lines = program.read_text().splitlines(keepends=True)
    (edited,) = [i for i, line in enumerate(lines) if line.strip() == "textmsg(message)"]
    lines[edited] = lines[edited].replace("(message)", "(mesage)")
    program.write_text("".join(lines))

    code, text = _invoke("check", str(plant), "--format", "sarif")
    assert code == 2  # a name never assigned is an error of check
    (run,) = sarif_valid(text)["runs"]
    (result,) = run["results"]
    place = result["locations"][0]["physicalLocation"]
    assert result["ruleId"] == "check/undefined-name" and result["properties"]["cell"] == "b/nozzle.toml"
    assert place["artifactLocation"]["uri"] == "plant/generated/nozzle_ur/ur/tcp_nozzle_ur_node.script"
    assert place["region"]["startLine"] == edited + 1

    code, text = _invoke("check", str(plant), "--format", "junit")
    suites = junit_valid(text).findall("testsuite")
    assert [(s.get("name"), s.get("failures"), s.get("errors")) for s in suites] == [
        ("check a/tray.toml", "0", "0"),
        ("check b/nozzle.toml", "1", "0"),
    ]
    assert [c.get("name") for s in suites for c in s.findall("testcase")] == ["pal_tray.prg", program.name]

    code, text = _invoke("check", str(plant), "--format", "github")
    assert text.startswith(f"::error file=plant/generated/nozzle_ur/ur/{program.name},line={edited + 1},")
    assert len(text.splitlines()) == 1


def test_a_plant_json_report_holds_no_times_and_the_timings_file_does(repo, plant, fake_verify):
    code, text = _invoke("verify", str(plant), "--json", "--timings", "times.json")
    assert code == 0
    times = json.loads((repo / "times.json").read_text())
    assert [cell["cell"] for cell in times["cells"]] == ["a/tray.toml", "b/gate.toml"]
    assert times["seconds"] > 0 and all(row["seconds"] >= 0 for cell in times["cells"] for row in cell["rows"])
    assert "programs" in times["cells"][0]["data"]

    def keys(data) -> set[str]:
        if isinstance(data, dict):
            return set(data) | {k for v in data.values() for k in keys(v)}
        return {k for v in data for k in keys(v)} if isinstance(data, list) else set()

    assert not keys(json.loads(text)) & {"seconds", "wall_seconds", "cases_per_second", "cases_per_s", "workers"}
    code, text = _invoke("verify", str(plant.parent / "plant" / "a" / "tray.toml"), "--timings", "t.json")
    assert code == 2 and "--timings: for a plant" in text


def test_another_output_folder_is_another_cache_entry(repo, plant, fake_verify):
    """The findings place the fresh programs in the plant's output folder: a plant with another `out` verifies
    again rather than report the programs where they are not written."""
    fake_verify.failing, fake_verify.mismatch = {"warehouse_dtrans"}, MISMATCH
    assert _invoke("verify", str(plant), "--format", "github")[0] == 1
    (plant / "codegen.toml").write_text('[plant]\nout = "programs"\n')
    code, text = _invoke("verify", str(plant), "--format", "github")
    assert code == 1 and fake_verify.calls == ["tray_dtrans", "warehouse_dtrans"] * 2
    assert text.startswith("::error file=plant/programs/warehouse_dtrans,line=7,")


def test_a_timings_file_in_no_folder_is_refused_before_any_cell_runs(repo, plant, fake_verify):
    code, text = _invoke("verify", str(plant), "--timings", "nowhere/times.json")
    assert code == 2 and "--timings nowhere/times.json: no folder" in text and fake_verify.calls == []
