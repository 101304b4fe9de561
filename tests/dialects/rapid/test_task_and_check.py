"""A RAPID task of several files (Rapid.programs, load_files), the tray cell written here, and `codegen check`."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from codegen.dialects.core.files import SourceFile, read_source
from codegen.dialects.core.values import RunError
from codegen.dialects.rapid import Rapid
from codegen.sim.gripper import Gripper

TRAY = Path(__file__).parent / "programs" / "tray_cell"


def tray_files() -> list[SourceFile]:
    return [read_source(p, Rapid.encodings) for p in sorted(TRAY.iterdir())]


def codes(findings) -> list[tuple[str, int, str]]:
    return [(Path(f.file).name, f.line, f.code) for f in findings]


# --- the program's files ------------------------------------------------------------------------------


def test_the_modules_given_together_are_one_program_with_main_first():
    main = "MODULE M\n PROC Main()\n ENDPROC\nENDMODULE\n"
    files = [SourceFile("a/lib.sys", "MODULE Lib\nENDMODULE\n"), SourceFile("b/cell.mod", main)]
    assert [[f.name for f in g] for g in Rapid.programs(files)] == [["b/cell.mod", "a/lib.sys"]]


def test_a_backups_tasks_are_one_program_each():
    main = "MODULE M\n  PROC main()\n  ENDPROC\nENDMODULE\n"
    files = [
        SourceFile("RAPID/TASK1/PROGMOD/m1.mod", main),
        SourceFile("RAPID/TASK1/SYSMOD/user.sys", "MODULE user(SYSMODULE)\nENDMODULE\n"),
        SourceFile("RAPID/TASK2/PROGMOD/m2.mod", main.replace("M\n", "M2\n")),
    ]
    groups = [[f.name for f in g] for g in Rapid.programs(files)]
    assert groups == [["RAPID/TASK1/PROGMOD/m1.mod", "RAPID/TASK1/SYSMOD/user.sys"], ["RAPID/TASK2/PROGMOD/m2.mod"]]


def test_two_mains_in_the_files_given_together_are_refused():
    main = "MODULE {0}\n  PROC main()\n  ENDPROC\nENDMODULE\n"
    files = [SourceFile("x/a.mod", main.format("A")), SourceFile("y/b.mod", main.format("B"))]
    with pytest.raises(RunError, match=r"x/a\.mod and y/b\.mod both define PROC main"):
        Rapid.programs(files)


def test_a_windows_1252_module_is_read():
    raw = 'MODULE M\n  PROC main()\n    TPWrite "Gr\xfc\xdfe";\n  ENDPROC\nENDMODULE\n'.encode("cp1252")
    from codegen.dialects.core.files import decode_text

    text = decode_text(raw, "m.mod", Rapid.encodings)
    assert Rapid.load_files([SourceFile("m.mod", text)]).run({}).messages == ["Grüße"]


def test_a_task_without_main_is_refused_naming_its_files():
    with pytest.raises(RunError, match=r"^a\.mod, b\.sys: no PROC main in the task's modules$"):
        Rapid.load_files([SourceFile("a.mod", "MODULE A\nENDMODULE\n"), SourceFile("b.sys", "MODULE B\nENDMODULE\n")])


# --- the tray cell: two modules written here ------------------------------------------------------------


def test_the_tray_cell_runs_with_every_move_and_passes_check():
    from codegen.robot.arms import find_arm

    (group,) = Rapid.programs(tray_files())
    assert Path(group[0].name).name == "MainModule.mod"
    assert Rapid.check_files(group) == []
    gripper, arm = Gripper("doGripper", "diGripClosed"), find_arm("IRB 1600-10/1.45")
    trace = Rapid.load_files(group).run({}, devices=[gripper], arm=arm)
    assert not trace.halted
    assert len(trace.moves) == 2 + 4 * 6 and all(m.joints is not None for m in trace.moves)
    assert trace.messages == ["Tray cell: start", "Tray full, parts: 4", "Cycle time [s]: 18.1"]
    assert [o.name for o in trace.outputs].count("doGripper") == 9
    assert trace.outputs[-1].name == "doTrayDone" and not trace.outputs[-1].value
    assert trace.moves[2].settings["accset"]["acc"] == 70.0
    assert trace.simulated_io["diGripClosed"] == "digital input"


def test_the_tray_cells_error_handler_retries_then_passes_the_error_on():
    (group,) = Rapid.programs(tray_files())
    trace = Rapid.load_files(group).run({})
    again = "Gripper not closed, once more"
    assert trace.messages[1:] == [again, again, "No part in the feeder"]
    assert trace.halted and trace.halt_message.startswith("ERR_WAIT_MAXTIME")


# --- codegen check ------------------------------------------------------------------------------------


def check(*modules: tuple[str, str], **kwargs):
    return Rapid.check_files([SourceFile(name, text) for name, text in modules], **kwargs)


def test_check_reports_every_syntax_error_of_every_file():
    bad = "MODULE A\n  PROC main()\n    x := 1\n    y := ;\n    MoveL p v100;\n  ENDPROC\nENDMODULE\n"
    other = "MODULE B\n  VAR num := 2;\nENDMODULE\n"
    assert codes(check(("a.mod", bad), ("b.mod", other))) == [
        ("a.mod", 4, "syntax"),
        ("a.mod", 5, "syntax"),
        ("b.mod", 2, "syntax"),
    ]


BROKEN = """MODULE Cell
  VAR num count := "three";
  VAR tooldata tEmpty;
  CONST robtarget p1 := [[500, 0, 400], [0, 0, 1, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]];
  VAR num a_name_that_is_longer_than_thirty_two := 0;
  PROC main()
    IF count THEN
      missing_routine 1;
    ENDIF
    total := 2;
    WaitDI diPart, 1;
    WaitUntil DInput(diDoor) = 1;
    MoveL p1, v2000, fine, tEmpty;
    MoveL p1, v100, fine, tEmpty \\WObj:=wobj0;
    TriggL p1, v100, trig, fine, tEmpty;
    count := StrLen(count) + "x";
  ENDPROC
ENDMODULE
"""


def test_check_reports_every_finding_of_a_module_with_file_and_line():
    found = check(("cell.mod", BROKEN), max_tcp_mm_s=1500)
    assert codes(found) == [
        ("cell.mod", 2, "type"),  # a string as a num's initial value
        ("cell.mod", 5, "name-length"),
        ("cell.mod", 7, "type"),  # IF num
        ("cell.mod", 8, "undefined-routine"),
        ("cell.mod", 10, "undefined-name"),
        ("cell.mod", 11, "wait-without-timeout"),
        ("cell.mod", 12, "wait-without-timeout"),
        ("cell.mod", 13, "speed"),
        ("cell.mod", 13, "tool"),  # tEmpty has no value
        ("cell.mod", 13, "work-object"),  # p1 with and without \WObj
        ("cell.mod", 14, "tool"),
        ("cell.mod", 15, "unsupported"),
        ("cell.mod", 16, "type"),  # StrLen of a num
        ("cell.mod", 16, "type"),  # num + string
    ]
    assert all("Python" not in f.message and "NoneType" not in f.message for f in found)
    severities = {f.code: f.severity for f in found}
    assert severities["unsupported"] == "unsupported" and severities["wait-without-timeout"] == "warning"


def test_check_of_a_clean_task_across_modules_is_empty_and_of_a_late_module_names_it():
    main = "MODULE M\n  PROC main()\n    helper 2;\n  ENDPROC\nENDMODULE\n"
    lib = 'MODULE L\n  PROC helper(num n)\n    TPWrite "" \\Num:=n;\n  ENDPROC\nENDMODULE\n'
    assert check(("m.mod", main), ("l.mod", lib)) == []
    wrong = lib.replace("helper(num n)", "helper(string s)").replace("\\Num:=n", "\\Num:=1")
    assert codes(check(("m.mod", main), ("l.mod", wrong))) == [("m.mod", 3, "type")]


def test_a_move_with_tool0_where_the_program_has_its_own_tool_is_a_warning():
    text = BROKEN.split("  PROC main()")[0].replace('"three"', "3")
    text = text.replace("a_name_that_is_longer_than_thirty_two", "n")
    text += "  PERS tooldata tGrip := [TRUE, [[0, 0, 100], [1, 0, 0, 0]], [1, [0, 0, 1], [1, 0, 0, 0], 0, 0, 0]];\n"
    text += "  PROC main()\n    MoveL p1, v100, fine, tool0;\n    MoveL p1, v100, fine, tGrip;\n  ENDPROC\nENDMODULE\n"
    assert codes(check(("cell.mod", text))) == [("cell.mod", 8, "tool")]


# --- the dialect's modules import each other one way ---------------------------------------------------


def test_the_rapid_modules_import_each_other_without_a_circle():
    folder = Path(Rapid.module("interpreter").__file__).parent
    graph = {}
    for path in folder.glob("*.py"):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        imported = set()
        for node in ast.walk(tree):  # at module level and inside functions
            if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("codegen.dialects.rapid"):
                if node.module == "codegen.dialects.rapid":
                    imported |= {alias.name for alias in node.names}
                else:
                    imported.add(node.module.rsplit(".", 1)[1])
        graph[path.stem] = imported & {p.stem for p in folder.glob("*.py")}

    def reaches(start, goal, seen=()):
        return any(n == goal or (n not in seen and reaches(n, goal, (*seen, n))) for n in graph.get(start, ()))

    assert [m for m in graph if reaches(m, m)] == []


def test_a_folder_of_robotware_7_modules_is_read(tmp_path):
    from click.testing import CliRunner

    from codegen.cli import main

    (tmp_path / "Main.modx").write_text('MODULE Main\n  PROC main()\n    TPWrite "seven";\n  ENDPROC\nENDMODULE\n')
    result = CliRunner().invoke(main, ["run", "--target", "abb", str(tmp_path)])
    assert result.exit_code == 0 and "message: seven" in result.output
    result = CliRunner().invoke(main, ["run", str(tmp_path)])  # RAPID is the language of one target only
    assert result.exit_code == 0 and "message: seven" in result.output
