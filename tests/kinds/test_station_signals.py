"""The controller-ready cell sections ([cell.vision], [cell.motion], [cell.io]) and the gripper's signal where the
stations grip and release."""

import re
from pathlib import Path

import pytest
from support import stations
from support.cells import replace_once
from support.programs import sources

from codegen.dialects.rapid.interpreter import load as load_rapid
from codegen.kinds.station.section import stations_of
from codegen.model.cell import CellError, cell_from_dict, load_cell
from codegen.render import render

SIGNAL = "  IF NOT VIS_SIGNAL() THEN\n    RETURN\n  ENDIF\n"
WORK_THEN_SIGNAL = "  $VEL.CP = 0.0500\n  LIN TARGET\n" + SIGNAL
SIGNAL_THEN_WORK = SIGNAL + "  $VEL.CP = 0.0500\n  LIN TARGET\n"
DEMO = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "agv_machine_tending.toml"


def _demo_dict() -> dict:
    import tomllib

    return tomllib.loads(DEMO.read_text(encoding="utf-8"))


@pytest.mark.parametrize(
    ("table", "values", "message"),
    [
        ("vision", {"timeout_s": 0.1}, r"cell\.vision\.timeout_s: must be in \[0\.2, 600\] s"),
        ("vision", {"timeout": 5}, r"cell\.vision\.timeout: unknown key"),
        ("motion", {"speed_mm_s": 0}, r"cell\.motion\.speed_mm_s: must be in \[1, 5000\] mm/s"),
        ("motion", {"zone_mm": 300}, r"cell\.motion\.zone_mm: must be in \[0, 200\] mm"),
        ("motion", {"retreat_mm": -5}, r"cell\.motion\.retreat_mm: must be in \[0, 1000\] mm"),
        ("motion", {"return_home": "yes"}, r"cell\.motion\.return_home: must be true or false"),
        ("motion", {"joint_speed_percent": 120}, r"cell\.motion\.joint_speed_percent: must be in \(0, 100\]"),
        ("io", {"output": {"ur": 9, "kuka": 17, "abb": "doX", "dtrans": 1}}, r"io\.output\.ur: expected a ur signal"),
        ("io", {"output": {"ur": 0, "kuka": 17, "dtrans": 1}}, r"cell\.io\.output\.abb: missing"),
        ("io", {"output": {"ur": 0, "kuka": 17, "abb": "do X", "dtrans": 1}}, r"io\.output\.abb: expected a signal"),
        ("io", {"feedback": {"ur": 0}}, r"cell\.io\.output: missing: the output the program sets at the work pose"),
    ],
)
def test_a_bad_section_names_its_key(table, values, message):
    data = _demo_dict()
    data["cell"][table] = values
    with pytest.raises(CellError, match=message):
        cell_from_dict(data, "cell.toml")


def test_the_demo_cell_names_its_speeds_zone_signal_and_timeout():
    cell = load_cell(DEMO)
    assert (cell.motion.speed_mm_s, cell.motion.work_speed_mm_s, cell.motion.zone_mm) == (250.0, 50.0, 10.0)
    assert cell.io.output["kuka"] == 17 and cell.io.feedback["abb"] == "diGripClosed"
    assert cell.vision.timeout_s == 5.0
    # the retreat: 50 mm back along the work pose's own z axis (the tool points down: 50 mm up)
    lathe = stations_of(cell)[0]
    work, retreat = lathe.poses[-1].matrix(), lathe.retreat.matrix()
    assert retreat[:3, 3] - work[:3, 3] == pytest.approx(-50.0 * work[:3, 2])


def test_a_signal_set_after_a_fly_by_point_is_set_while_the_arm_moves():
    """RAPID runs ahead of a fly-by point: SetDO then acts before the arm arrives; after a fine point it waits."""
    module = (
        "MODULE m\n  PROC main()\n"
        "    MoveL [[500,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;\n"
        "    MoveL [[600,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, {zone}, tool0;\n"
        "    SetDO doGrip, 1;\n  ENDPROC\nENDMODULE\n"
    )
    for zone, moving in (("z10", True), ("fine", False)):
        trace = load_rapid(module.replace("{zone}", zone), "m.mod").run({})
        (event,) = trace.outputs
        assert (event.name, event.value, event.after_moves, event.moving) == ("doGrip", True, 2, moving)


def test_krl_continue_lets_the_output_run_ahead_of_the_motion():
    """KSS 8: CONTINUE before `$OUT[n] = ...` keeps the advance run going, so the output changes while the
    arm still moves to the last point; without it the output waits for the arm. KRL has no loop-continue."""
    from codegen.dialects.krl.interpreter import load as load_krl

    src = (
        "DEF t()\n  DECL INT I\n  PTP {X 500, Y 0, Z 400, A 0, B 90, C 0}\n  LIN {X 600, Y 0, Z 400, A 0, B 90, C 0}\n"
        "{cont}  $OUT[17] = TRUE\n  I = 0\n  WHILE I < 2\n    CONTINUE\n    I = I + 1\n  ENDWHILE\nEND\n"
    )
    for cont, moving in (("  CONTINUE\n", True), ("", False)):
        trace = load_krl(src.replace("{cont}", cont), "t.src").run({})
        (event,) = trace.outputs
        assert (event.name, event.value, event.after_moves, event.moving) == ("$OUT[17]", True, 2, moving)


@pytest.fixture(scope="module")
def demo():
    cell = load_cell(DEMO)
    return cell, stations.build_cases(cell, 2, 5)


def _mismatches(cell, cases, target: str, edit) -> list[str]:
    text, _dat = stations.files(cell, target)
    return stations.verify(cell, stations.source(cell, target, edit(text)), cases).first_mismatches


@pytest.mark.parametrize(
    ("target", "old", "new", "says"),
    [
        # the gripper never closed on the finished part
        (
            "ur",
            "    vis_signal()\n",
            "",
            "expected standard_digital_out[0] set to True after move 3 (grip at chuck_out)",
        ),
        # the grip before the move into the chuck: the gripper closes at the approach, a move before the plan's grip
        (
            "kuka",
            WORK_THEN_SIGNAL,
            SIGNAL_THEN_WORK,
            "set to True after move 2, expected $OUT[17] set to True after move 3 (grip at chuck_out)",
        ),
        # CONTINUE: the gripper closes while the arm still moves into the work pose
        ("kuka", "  $OUT[17] = TRUE\n", "  CONTINUE\n  $OUT[17] = TRUE\n", "while the arm moves"),
        # no wait for the feedback: the station goes on without the gripper closed
        ("abb", "    WaitDI diGripClosed, 1 \\MaxTime:=IO_TIMEOUT;\n", "", "gripper_silent"),
        ("abb", "    WaitDI diGripClosed, 0 \\MaxTime:=IO_TIMEOUT;\n", "", "gripper_stuck"),
        # the feedback read from the wrong input: it never comes
        ("dtrans", "While DIn(2) <> True", "While DIn(3) <> True", "no feedback from the gripper in 2 s"),
        # nothing done with the gripper at the start: neither opened nor held on to
        ("ur", "  vis_gripper_start()\n", "", "(at home, as the gripper starts)"),
        ("kuka", "  IF NOT VIS_GRIPPER_START() THEN\n    RETURN\n  ENDIF\n", "", "(at home, as the gripper starts)"),
        # the gripper opened at the start whatever it holds: a part held there is dropped at home
        ("ur", "    if get_standard_digital_in(1) == True:\n", "    if False:\n", "part_held"),
        ("abb", "    IF DInput(diGripClosed) = 1 THEN\n", "    IF FALSE THEN\n", "part_held"),
    ],
)
def test_verify_fails_a_broken_signal(demo, target, old, new, says):
    cell, cases = demo
    found = _mismatches(cell, cases, target, lambda text: replace_once(text, old, new))
    assert found and any(says in m for m in found), found[:3]


def test_the_signal_is_in_every_demo_program():
    cell = load_cell(DEMO)
    text = {f.relpath.rsplit("/", 1)[1]: f.text for f in render(cell)}
    assert re.search(r"set_standard_digital_out\(0, True\)", text["agv_machine_tending.script"])
    krl = text["agv_machine_tending.src"]
    assert "$OUT[17] = TRUE" in krl and "WHILE $IN[18] <> TRUE" in krl and "$OUT[17] = FALSE" in krl
    assert "SetDO doGripClose, 1;" in text["agv_machine_tending.mod"]
    assert "SetDO 1, True" in text["agv_machine_tending.prg"]


@pytest.mark.parametrize(
    ("target", "old", "new"),
    [
        # no check where the arm stands: the program moves home from wherever the arm was left
        ("ur", '    vis_stop("start with the arm at home', '    textmsg("start with the arm at home'),
        ("abb", '      vis_stop "start with the arm at home', '      TPWrite "start with the arm at home'),
    ],
)
def test_verify_fails_a_start_away_from_home_that_moves(demo, target, old, new):
    cell, cases = demo
    found = _mismatches(cell, cases, target, lambda text: replace_once(text, old, new))
    says = "expected a stop ('start with the arm at home"
    assert any(m.startswith("start_away") and says in m for m in found), found[:3]


@pytest.mark.parametrize(
    ("target", "old", "new"),
    [  # station 1's retreat (the start_retreat case's station) no longer accepted as a start
        ("ur", "  vis_known = vis_known or vis_near(", "  vis_known = vis_known or False and vis_near("),
        ("abb", "    known := known OR vis_near(", "    known := known OR FALSE AND vis_near("),
    ],
)
def test_verify_fails_a_program_that_refuses_to_start_at_a_retreat(demo, target, old, new):
    cell, cases = demo
    found = _mismatches(cell, cases, target, lambda text: replace_once(text, old, new))
    assert [m for m in found if m.startswith("start_retreat")] and all(
        m.startswith("start_retreat") and "unexpected stop: 'start with the arm at home or a retreat" in m
        for m in found
    ), found[:3]


def test_a_program_started_away_from_home_stops_there_or_goes_home_by_its_controller(demo):
    """UR and RAPID refuse to move (a restart must not move straight to a station); KRL's first PTP home
    is the BCO run, from anywhere."""
    cell, cases = demo
    away = [c for c in cases if c.start == "away"]
    assert len(away) == 1
    for target in ("ur", "abb", "kuka"):
        assert stations.verify(cell, stations.source(cell, target), away).mismatches == 0


BENCH = DEMO.with_name("thermometer_bench.toml")


@pytest.fixture(scope="module")
def programs():
    """Every example cell's programs by file name."""
    return {f.relpath.rsplit("/", 1)[1]: f.text for path in (DEMO, BENCH) for f in render(load_cell(path))}


def test_the_review_list_is_cleared_in_the_generated_text(programs):
    """The issue's review items that are visible in the text (each also has a behaviour test in verify)."""
    for name, text in programs.items():
        if name.endswith(".dat"):  # the cells' data are the program's own: two cells coexist on one KRC
            assert "DECL GLOBAL" not in text, name
            assert all(f"VIS_PAR[{i}]={{PAR_TYPE #EMPTY}}" in text for i in (1, 2, 3)), name
        if name.endswith(".src"):
            # the arm stops, then the request
            assert re.search(r"WAIT SEC 0 ;[^\n]*\n  VIS_REQ = VIS_REQ \+ 1\n", text), name
            assert "$BASE = $ROBROOT" in text and "$BASE = $NULLFRAME" not in text, name
            # KUKA's start section: the stop-message interrupt, then the default speeds and accelerations
            ini = "  GLOBAL INTERRUPT DECL 3 WHEN $STOPMESS==TRUE DO IR_STOPM()\n  INTERRUPT ON 3\n  BAS(#INITMOV, 0)\n"
            assert ini in text, name
            assert re.search(r"SET_KRLMSG\(#QUIT[^\n]*\n  WHILE EXISTS_KRLMSG\(VIS_HANDLE\)", text), name
        if name.endswith(".mod"):
            routines = re.findall(r"^  (LOCAL )?(PROC|FUNC) (\w+)", text, re.MULTILINE)
            assert [r[2] for r in routines if not r[0]] == ["main"], name  # only the entry is global
            assert not re.search(r"^    VAR wobjdata", text, re.MULTILINE), name  # work objects at module level
            assert "EXIT;" not in text.replace("    Stop;\n    EXIT;", ""), name  # a stop the operator sees first
            assert all("\\MaxTime" in line for line in text.splitlines() if line.strip().startswith("WaitUntil")), name
            assert re.search(r"^  ERROR\n", text, re.MULTILINE), name
        if name.endswith(".script"):
            body = text.split("  def vis_stop(message):", 1)[1].split("\n  end\n", 1)[1]
            assert not re.search(r"^\s+halt$", body, re.MULTILINE), name  # every other stop shows the popup
            assert "popup(message" in text and "is_steady()" in text, name


def test_the_ur_program_comes_for_the_socket_and_for_a_script_node(demo):
    """One `def` at column 1, other lines indented, `end` at column 1 is what URControl recognises on port
    30002 (URScript manual, Connecting to URControl); a Script node runs its lines where it stands, so its
    file has no `def` around them. Both move the same."""
    cell, cases = demo
    files = {f.relpath.rsplit("/", 1)[1]: f.text for f in render(cell, ["ur"])}
    socket, node = files["agv_machine_tending.script"], files["agv_machine_tending_node.script"]
    lines = socket.splitlines()
    assert lines[0] == "def agv_machine_tending():" and lines[-1] == "end"
    assert all(line == "" or line[0] == " " for line in lines[1:-1])
    assert not re.search(r"^\S", node, re.MULTILINE)  # nothing at column 1: no program of its own
    assert "agv_machine_tending_node.script" in socket and "socket interface (port 30002)" in node
    programs = [s for s in sources(cell, "ur") if s.files[0].text in (socket, node)]
    assert len(programs) == 2  # the socket program and its Script-node twin: two programs
    for program in programs:
        report = stations.verify(cell, program, cases)
        assert report.cases == len(cases) and not report.first_mismatches, (program.ident, report.first_mismatches[:3])
