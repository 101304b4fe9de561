"""verify's and check's findings as JUnit, SARIF and GitHub annotations: valid against the published schemas, and
a hand-edited program's finding at the line that was edited."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.model.cell import EXAMPLES_DIR, load_cell
from codegen.reports.findings import CellResult, Finding, Location, TestCase
from codegen.reports.formats import write
from codegen.reports.from_verify import verify_result
from codegen.reports.github import github
from codegen.verify import engine
from codegen.verify.engine import Options, verify_cell

DEMO = EXAMPLES_DIR / "agv_machine_tending.toml"
GENERATED = Path(__file__).resolve().parents[2] / "generated" / "agv_machine_tending"
FAST = Options(cases=1, jobs=1, sweeps=False, scenarios=frozenset({"random"}))


@pytest.fixture(scope="module")
def cell():
    return load_cell(DEMO)


def copied(tmp_path: Path, target: str, name: str) -> Path:
    """The demo's program files of a target copied into tmp_path/<target>/; the path of the one named."""
    folder = tmp_path / target
    folder.mkdir()
    for f in (GENERATED / target).iterdir():
        (folder / f.name).write_text(f.read_text(encoding="utf-8"), encoding="utf-8")
    return folder / name


def edit_line(path: Path, needle: str, old: str, new: str) -> int:
    """Replace old by new on the one line that holds needle; its number."""
    lines = path.read_text(encoding="utf-8").splitlines(keepends=True)
    (i,) = [i for i, line in enumerate(lines) if needle in line]
    assert old in lines[i]
    lines[i] = lines[i].replace(old, new, 1)
    path.write_text("".join(lines), encoding="utf-8")
    return i + 1


def line_of(path: Path, number: int) -> str:
    return path.read_text(encoding="utf-8").splitlines()[number - 1]


def region(location: dict) -> tuple[str, int]:
    physical = location["physicalLocation"]
    return physical["artifactLocation"]["uri"], physical["region"]["startLine"]


@pytest.fixture(scope="module")
def ur_edit(cell, tmp_path_factory):
    """The demo's UR program with station 1's chuck pose moved 1 mm in x (one line of the copy), verified."""
    root = tmp_path_factory.mktemp("repo")
    path = copied(root, "ur", "agv_machine_tending.script")
    line = edit_line(path, "p1_chuck = p[", "0.7385000", "0.7395000")
    report = verify_cell(cell, [path], ("ur",), FAST)
    return root, path, line, verify_result(report, str(DEMO))


def test_a_hand_edited_pose_is_a_sarif_finding_at_the_edited_line(ur_edit, sarif_valid):
    root, path, line, result = ur_edit
    log = sarif_valid(write("sarif", [result], root))
    (run,) = log["runs"]
    rules = [r["id"] for r in run["tool"]["driver"]["rules"]]
    at = {(r["ruleId"], *region(r["locations"][0])) for r in run["results"]}
    assert ("verify/edit", "ur/agv_machine_tending.script", line) in at
    edit = next(r for r in run["results"] if r["ruleId"] == "verify/edit")
    assert edit["locations"][0]["physicalLocation"]["artifactLocation"]["uriBaseId"] == "SRCROOT"
    assert "0.7395000" in edit["message"]["text"]
    # the mismatch: at the line of the move that went wrong, with the edited line and the cell's key beside it
    poses = [r for r in run["results"] if r["ruleId"] == "verify/pose"]
    assert poses and all(r["level"] == "error" for r in poses)
    for result in poses:
        uri, move_line = region(result["locations"][0])
        assert uri == "ur/agv_machine_tending.script"
        assert line_of(path, move_line).lstrip().startswith("movel(") and "p1_chuck" in line_of(path, move_line)
        related = [region(r) for r in result["relatedLocations"]]
        assert ("ur/agv_machine_tending.script", line) in related
        cell_uri, cell_line = related[0]
        assert cell_uri.endswith("agv_machine_tending.toml") and not cell_uri.startswith("/")  # outside root: file:
        assert DEMO.read_text().splitlines()[cell_line - 1].startswith("chuck = [738.5")
        assert rules[result["ruleIndex"]] == "verify/pose"
    assert all(rules[r["ruleIndex"]] == r["ruleId"] for r in run["results"])
    help_texts = {r["id"]: r["help"]["text"] for r in run["tool"]["driver"]["rules"]}
    assert "tolerance" in help_texts["verify/pose"]


def test_a_verified_program_is_one_junit_case_that_fails_with_its_mismatch(ur_edit, junit_valid):
    _, _, _, result = ur_edit
    root = junit_valid(write("junit", [result], Path.cwd()))
    (suite,) = root.findall("testsuite")
    (case,) = suite.findall("testcase")
    assert (case.get("name"), case.get("classname")) == ("agv_machine_tending", "verify.agv_machine_tending.ur")
    (failure,) = case.findall("failure")
    assert "position error" in failure.text and "line" in failure.text
    assert suite.get("tests") == "1" and suite.get("failures") == "1"


def test_a_program_as_generated_passes_and_has_no_findings(cell, tmp_path, junit_valid, sarif_valid):
    path = copied(tmp_path, "ur", "agv_machine_tending.script")
    result = verify_result(verify_cell(cell, [path], ("ur",), FAST), str(DEMO))
    assert result.findings == []
    (case,) = junit_valid(write("junit", [result], tmp_path)).iter("testcase")
    assert case.find("failure") is None
    assert sarif_valid(write("sarif", [result], tmp_path))["runs"][0]["results"] == []
    assert write("github", [result], tmp_path) == ""


def test_a_krl_pose_edited_in_the_data_list_points_at_the_dat_line_and_the_move_in_the_src(cell, tmp_path, sarif_valid):
    src = copied(tmp_path, "kuka", "agv_machine_tending.src")
    dat = src.with_suffix(".dat")
    line = edit_line(dat, "DECL E6POS P1_CHUCK=", "X 738.5000", "X 739.5000")
    result = verify_result(verify_cell(cell, [src], ("kuka",), FAST), str(DEMO))
    run = sarif_valid(write("sarif", [result], tmp_path))["runs"][0]
    at = {(r["ruleId"], *region(r["locations"][0])) for r in run["results"]}
    assert ("verify/edit", "kuka/agv_machine_tending.dat", line) in at
    moves = [region(r["locations"][0]) for r in run["results"] if r["ruleId"] == "verify/pose"]
    assert moves and all(uri == "kuka/agv_machine_tending.src" for uri, _ in moves)
    assert all(line_of(src, n).lstrip().startswith("LIN") for _, n in moves)


def test_github_annotations_escape_what_the_runner_reads_as_syntax():
    finding = Finding("check/syntax", "100% wrong\r\nnext: a, b", "error", Location("/repo/dir/a,b:c%.script", 3, 5))
    result = CellResult("check", "", None, [TestCase("", "ur", "a", failure="x", findings=[finding])])
    (line,) = github([result], Path("/repo")).splitlines()
    assert line == "::error file=dir/a%2Cb%3Ac%25.script,line=3,col=5,title=check/syntax::100%25 wrong%0D%0Anext: a, b"
    note = Finding("verify/edit", "x", "warning", Location("/elsewhere/p.script", 1))
    (line,) = github(
        [CellResult("verify", "c,1", None, [TestCase("c", "ur", "p", findings=[note])])], Path("/repo")
    ).splitlines()
    assert line.startswith("::warning title=verify/edit (c%2C1)::")  # outside the repository: no file


BAD_UR = """def prog():
  while not get_standard_digital_in(0):
    sync()
  end
  x = y + 1
end
"""


def test_check_formats(tmp_path, monkeypatch, sarif_valid, junit_valid):
    (tmp_path / ".git").mkdir()  # the repository root the paths are relative to
    (tmp_path / "cells").mkdir()
    program = tmp_path / "cells" / "prog.script"
    program.write_text(BAD_UR)
    monkeypatch.chdir(tmp_path / "cells")
    runner = CliRunner()
    out = {f: runner.invoke(main, ["check", "prog.script", "--format", f]) for f in ("sarif", "junit", "github")}
    assert {r.exit_code for r in out.values()} == {2}, {f: r.output for f, r in out.items()}
    run = sarif_valid(out["sarif"].output)["runs"][0]
    found = {(r["ruleId"], r["level"], *region(r["locations"][0])) for r in run["results"]}
    assert found == {
        ("check/wait-without-timeout", "warning", "cells/prog.script", 2),
        ("check/undefined-name", "error", "cells/prog.script", 5),
    }
    (case,) = junit_valid(out["junit"].output).iter("testcase")
    assert case.get("name") == "prog.script" and "undefined-name" in case.find("failure").text
    lines = out["github"].output.splitlines()
    assert lines[0].startswith("::warning file=cells/prog.script,line=2,col=")
    assert lines[1].startswith("::error file=cells/prog.script,line=5,col=")
    both = runner.invoke(main, ["check", "prog.script", "--format", "sarif", "--json"])
    assert both.exit_code == 2 and "choose one" in both.output


def test_verify_command_writes_the_format_asked(cell, tmp_path, monkeypatch):
    """The command's --format: the engine run with few cases (the formats' contents are the tests above)."""

    def fast(model, files, targets, options):
        return verify_cell(model, files, targets, FAST)

    monkeypatch.setattr(engine, "verify_cell", fast)
    (tmp_path / ".git").mkdir()
    path = copied(tmp_path, "ur", "agv_machine_tending.script")
    line = edit_line(path, "p1_chuck = p[", "0.7385000", "0.7395000")
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(main, ["verify", str(DEMO), "ur/agv_machine_tending.script", "--format", "github"])
    assert result.exit_code == 1, result.output
    assert f"::warning file=ur/agv_machine_tending.script,line={line},title=verify/edit" in result.output
    assert re.search(r"^::error file=ur/agv_machine_tending.script,line=\d+,title=verify/pose", result.output, re.M)
    both = CliRunner().invoke(main, ["verify", str(DEMO), "--json", "--format", "junit"])
    assert both.exit_code == 2 and "choose one" in both.output


def test_a_hand_edited_speed_is_a_move_setting_mismatch_at_the_edited_line(cell, tmp_path, sarif_valid):
    path = copied(tmp_path, "ur", "agv_machine_tending.script")
    line = edit_line(path, "movel(pose_trans(corr, p1_chuck)", "v=0.0500", "v=0.1000")
    result = verify_result(verify_cell(cell, [path], ("ur",), FAST), str(DEMO))
    run = sarif_valid(write("sarif", [result], tmp_path))["runs"][0]
    at = {(r["ruleId"], *region(r["locations"][0])) for r in run["results"]}
    assert ("verify/move-setting", "ur/agv_machine_tending.script", line) in at  # the move is the edited line
    assert ("verify/edit", "ur/agv_machine_tending.script", line) in at
    assert not any(rule == "verify/pose" for rule, _, _ in at)


def test_fresh_programs_are_placed_where_generate_writes_them():
    from codegen.verify.report import Report, Row

    row = Row("point", "ur", "prog", ["<fresh>/bench/ur/prog.script"], cases=3)
    row.mismatch(
        "random station 1 reading (1, 2, 3): move 2 (work, line 40): position error 1 mm",
        "move 2 (work, line 40): position error 1 mm",
    )
    result = verify_result(Report("bench", [row], 0, 3), None, Path("generated"))
    (finding,) = result.findings
    assert finding.program == Location(str(Path("generated") / "bench" / "ur" / "prog.script"), 40)
    assert finding.rule == "verify/pose" and finding.cell is None
    assert result.cases[0].failure.startswith("1 of 3 cases do not match the reference")


def test_junit_stays_xml_with_control_characters_in_a_message(junit_valid):
    finding = Finding("check/syntax", "bad \x00 byte \x1b[31m", "error", Location("p.script", 1))
    case = TestCase(
        "", "ur", "p.script", ["p.script"], findings=[finding], failure="p.script:1: bad \x00 byte \x1b[31m"
    )
    root = junit_valid(write("junit", [CellResult("check", "", None, [case])], Path.cwd()))
    assert "bad \\x00 byte \\x1b[31m" in next(root.iter("failure")).text


def test_a_removed_line_is_a_warning_after_the_line_before_it_and_the_case_passes(cell, tmp_path, junit_valid):
    path = copied(tmp_path, "ur", "agv_machine_tending.script")
    lines = path.read_text(encoding="utf-8").splitlines(keepends=True)
    at = next(i for i, line in enumerate(lines) if "generated, do not edit" in line)
    path.write_text("".join(lines[:at] + lines[at + 1 :]), encoding="utf-8")
    result = verify_result(verify_cell(cell, [path], ("ur",), FAST), str(DEMO))
    (finding,) = result.findings
    assert (finding.rule, finding.level, finding.program.line) == ("verify/edit", "warning", at)
    assert "removed after this line: # generated, do not edit" in finding.message
    (case,) = junit_valid(write("junit", [result], tmp_path)).iter("testcase")
    assert case.find("failure") is None
