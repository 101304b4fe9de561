"""RAPID's standard environment: predefined data, signals, the FlexPendant, motion settings, clocks, functions."""

from __future__ import annotations

import numpy as np
import pytest

from codegen.dialects.core.values import RunError
from codegen.dialects.rapid.interpreter import load
from codegen.sim.gripper import Gripper

TARGET = "[[{x}, 0, 500], [1, 0, 0, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]]"
P0, P400 = TARGET.format(x=0), TARGET.format(x=400)


def mod(body: str, decls: str = "", routines: str = "") -> str:
    return f"MODULE T\n{decls}\nPROC main()\n{body}\nENDPROC\n{routines}\nENDMODULE\n"


def run(body: str, decls: str = "", routines: str = "", **kwargs):
    return load(mod(body, decls, routines), "t.mod").run({}, **kwargs)


# --- predefined data --------------------------------------------------------------------------------


def test_predefined_data_initialise_module_data():
    """Was a traceback: `VAR zonedata z := z50;` at module level."""
    decls = "VAR zonedata z := z50;\nVAR speeddata s := v1000;\nPERS tooldata t := tool0;\nVAR wobjdata w := wobj0;"
    body = 'TPWrite "" \\Num:=z.pzone_tcp + z.zone_ori;\nTPWrite "" \\Num:=s.v_tcp + s.v_ori;'
    body += '\nTPWrite "" \\Num:=t.tload.mass * 1000;\nTPWrite "" \\Bool:=w.ufprog;'
    body += '\nTPWrite "" \\Num:=load0.cog.z * 1000;'
    assert run(body, decls).messages == ["57.5", "1500", "1", "TRUE", "1"]


def test_predefined_data_are_values_a_move_takes_and_names_in_its_settings():
    trace = run(f"MoveL {P0}, v100, z10, tool0;\nMoveL {P400}, s, fine, tool0;", "VAR speeddata s := vmax;")
    assert [(m.settings["speed"], m.settings["zone"], m.settings["tool"]) for m in trace.moves] == [
        ("V100", "Z10", "TOOL0"),
        ("VMAX", "FINE", "TOOL0"),
    ]
    assert trace.moves[0].settings["zone_mm"] == 10.0 and trace.moves[0].settings["load"] is None


def test_a_name_that_is_not_predefined_data_is_undefined_when_loaded():
    with pytest.raises(RunError, match=r"t\.mod:4:\d+: undefined variable v123"):
        load(mod(f"MoveL {P0}, v123, fine, tool0;"), "t.mod")


# --- signals ------------------------------------------------------------------------------------------


def test_signal_instructions_record_every_output_and_the_simulated_io():
    body = "Set doLamp;\nReset doLamp;\nSetDO doValve, 1;\nSetDO \\SDelay:=0.5, doValve, 0;\nPulseDO doHorn;"
    body += "\nPulseDO \\PLength:=1.5, doHorn;\nInvertDO doLamp;\nSetGO goCode, 12;\nSetAO aoSpeed, 2.5;"
    trace = run(body)
    assert [(o.name, o.value, round(o.time, 3)) for o in trace.outputs] == [
        ("doLamp", True, 0.0),
        ("doLamp", False, 0.0),
        ("doValve", True, 0.0),
        ("doValve", False, 0.5),
        ("doHorn", True, 0.0),
        ("doHorn", False, 0.2),
        ("doHorn", True, 0.0),
        ("doHorn", False, 1.5),
        ("doLamp", True, 0.0),
    ]
    assert trace.simulated_io == {
        "doLamp": "digital output",
        "doValve": "digital output",
        "doHorn": "digital output",
        "goCode": "group output",
        "aoSpeed": "analog output",
    }


def test_signals_read_by_functions_and_as_values():
    body = (
        'SetDO doLamp, 1;\nSetGO goCode, 5;\nTPWrite "" \\Num:=doLamp + DOutput(doLamp) + GOutput(goCode);'
        '\nTPWrite "" \\Num:=diReady + DInput(diReady) + GInput(giRecipe);\nTPWrite "" \\Bool:=TestDI(diReady);'
        "\nWaitDI diReady, 1;\nWaitUntil diReady = 1;"
    )
    trace = run(body, signals={"diReady": True, "giRecipe": 7})
    assert trace.messages == ["7", "9", "TRUE"]


def test_wait_di_with_a_gripper_and_without_an_answer():
    body = 'Set doGrip;\nWaitDI diClosed, 1 \\MaxTime:=2;\nWaitDO doGrip, 1;\nTPWrite "closed";'
    assert run(body, devices=[Gripper("doGrip", "diClosed")]).messages == ["closed"]
    trace = run(body)
    assert trace.halted and trace.halt_message.startswith("ERR_WAIT_MAXTIME")
    with pytest.raises(RunError, match=r"t\.mod:4:1: WaitDI a condition that nothing here makes true"):
        run("WaitDI diClosed, 1;")


def test_a_signal_variable_connected_with_alias_io():
    decls = "VAR signaldo doMine;"
    trace = run('AliasIO "DO10_1", doMine;\nSet doMine;', decls)
    assert [(o.name, o.value) for o in trace.outputs] == [("DO10_1", True)]
    with pytest.raises(RunError, match=r"t\.mod:4:1: signal variable doMine is not connected"):
        run("Set doMine;", decls)


def test_a_signal_cannot_be_assigned():
    with pytest.raises(RunError, match=r"t\.mod:5:1: doLamp is a signal"):
        load(mod("Set doLamp;\ndoLamp := 1;"), "t.mod")


# --- the FlexPendant --------------------------------------------------------------------------------


def test_tp_write_values_and_tp_erase():
    body = 'TPErase;\nTPWrite "n=" \\Num:=2.5;\nTPWrite "b=" \\Bool:=TRUE;\nTPWrite "p=" \\Pos:=[1, 2.5, 3];'
    assert run(body).messages == ["n=2.5", "b=TRUE", "p=[1,2.5,3]"]


def test_tp_read_fk_and_tp_read_num_take_the_operators_answers_in_order():
    from codegen.sim.operator import Operator  # the run's operator (Program.run's devices, codegen run --answer)

    body = 'TPReadFK key, "Go on?", "Yes", stEmpty, stEmpty, stEmpty, "No";\nTPReadNum n, "How many?";'
    body += '\nTPWrite "" \\Num:=key * 100 + n;'
    trace = run(body, "VAR num key;\nVAR num n;", devices=[Operator([5, 12])])
    assert trace.messages == ["Go on?", "How many?", "512"]
    with pytest.raises(RunError, match=r"t\.mod:5:1: TPReadFK: the operator.s answer 2 is not one .*\(1 Yes, 5 No\)"):
        run(body, "VAR num key;\nVAR num n;", devices=[Operator([2])])
    with pytest.raises(RunError, match=r"t\.mod:5:1: TPReadFK: the program waits for the operator") as refused:
        run(body, "VAR num key;\nVAR num n;")
    # the message names how a run gets an operator, and \MaxTime, which goes on without one
    text = str(refused.value)
    assert "(codegen run --answer)" in text and text.endswith("give TPReadFK \\MaxTime to go on without one")


def test_tp_read_num_max_time_without_an_answer_sets_the_break_flag():
    body = 'TPReadNum n, "How many?" \\MaxTime:=3 \\BreakFlag:=e;\nTPWrite "" \\Num:=e;\nWaitTime 0;'
    trace = run(body, "VAR num n;\nVAR errnum e;")
    assert trace.messages[1] != "0" and not trace.halted


# --- motion settings --------------------------------------------------------------------------------


def test_acc_set_vel_set_and_sing_area_are_in_every_later_moves_settings():
    body = f"MoveL {P0}, v100, fine, tool0;\nAccSet 50, 100;\nVelSet 50, 150;\nSingArea \\Wrist;"
    body += f"\nMoveL {P400}, v200, fine, tool0;\nWaitTime 0;"
    trace = run(body)
    first, second = trace.moves
    assert "accset" not in first.settings
    assert second.settings["accset"] == {"acc": 50.0, "ramp": 100.0, "line": 5}
    assert second.settings["velset"] == {"override": 50.0, "max": 150.0, "line": 6}
    assert second.settings["singarea"] == {"mode": "wrist", "line": 7}
    assert second.settings["tcp_mm_s"] == 200.0  # the programmed speed; VelSet changes the time
    assert second.end_time - first.end_time == pytest.approx(400 / 100)  # min(200 * 50 %, 150) mm/s


def test_conf_and_grip_load_are_recorded():
    body = f"ConfL \\Off;\nGripLoad piece;\nMoveL {P0}, v100, fine, tool0;"
    settings = run(body, "PERS loaddata piece := [2.5, [0, 0, 40], [1, 0, 0, 0], 0, 0, 0];").moves[0].settings
    assert settings["confl"] == {"on": False, "line": 4}
    grip = {"mass": 2.5, "cog": [0.0, 0.0, 40.0], "aom": [1.0, 0.0, 0.0, 0.0], "moments": [0.0, 0.0, 0.0], "line": 5}
    assert settings["gripload"] == grip


# --- data instructions, clocks and functions --------------------------------------------------------


def test_incr_decr_add_clear_and_clocks():
    body = "Incr n;\nIncr n;\nDecr n;\nAdd n, 10;\nClkReset c;\nClkStart c;\nWaitTime 1.25;\nClkStop c;"
    body += '\nWaitTime 3;\nTPWrite "" \\Num:=n;\nTPWrite "" \\Num:=ClkRead(c);\nClear n;\nTPWrite "" \\Num:=n;'
    assert run(body, "VAR num n;\nVAR clock c;").messages == ["11", "1.25", "0"]


STRINGS = [
    ('StrPart("robot", 2, 3)', "obo"),
    ('StrMap("abc", "ab", "xy")', "xyc"),
    ("NumToStr(3.14159, 2)", "3.14"),
    ("ValToStr([1, 2.5, 3])", "[1,2.5,3]"),
]
NUMBERS = [
    ('StrLen("robot")', "5"),
    ('StrFind("a,b;c", 1, ",;")', "2"),
    ('StrMatch("abcabc", 2, "ab")', "4"),
    ("Round(2.456 \\Dec:=2)", "2.46"),
    ("Trunc(2.456 \\Dec:=1)", "2.4"),
    ("Pow(2, 10)", "1024"),
    ("ACos(0)", "90"),
    ("Sqrt(16) + Abs(-1)", "5"),
    ("BitAnd(12, 10)", "8"),
    ("Distance([0, 0, 0], [3, 4, 0])", "5"),
]


@pytest.mark.parametrize(("expression", "shown"), STRINGS + NUMBERS)
def test_string_and_math_functions(expression, shown):
    body = f"TPWrite {expression};" if (expression, shown) in STRINGS else f'TPWrite "" \\Num:={expression};'
    assert run(body).messages == [shown]


def test_str_to_val_sets_the_variable_only_for_a_literal_of_its_type():
    body = 'ok := StrToVal("12.5", n);\nTPWrite "" \\Num:=n;\nok := StrToVal("abc", n);\nTPWrite "" \\Bool:=ok;'
    body += '\nok := StrToVal("[1,2,3]", p);\nTPWrite "" \\Num:=p.y;'
    assert run(body, "VAR num n;\nVAR bool ok;\nVAR pos p;").messages == ["12.5", "FALSE", "2"]


def test_offs_and_rel_tool():
    decls = f"VAR robtarget p := {P400};\nVAR robtarget q;"
    body = "q := RelTool(p, 10, 0, 5 \\Rz:=90);\nMoveL Offs(q, 0, 0, -5), v100, fine, tool0;"
    trace = run(body, decls)
    pose = trace.moves[0].tcp2base
    assert pose[:3, 3] == pytest.approx([410, 0, 500])  # the tool's x and z are the base's x and z here
    assert pose[:3, :3] @ np.array([1, 0, 0]) == pytest.approx([0, 1, 0], abs=1e-6)


def test_crobt_and_cjointt_read_where_the_arm_is():
    from codegen.robot.arms import find_arm

    joints = "CONST jointtarget home := [[0, 0, 0, 0, 90, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]];"
    body = "MoveAbsJ home, v100, fine, tool0;\nj := CJointT();\np := CRobT(\\Tool:=tool0 \\WObj:=wobj0);"
    body += '\nTPWrite "" \\Num:=j.robax.rax_5;\nTPWrite "" \\Num:=Round(p.trans.z);'
    trace = run(body, joints + "\nVAR jointtarget j;\nVAR robtarget p;", arm=find_arm("IRB 1600-10/1.45"))
    assert trace.messages[0] == "90" and float(trace.messages[1]) > 0


def test_an_instruction_the_interpreter_does_not_model_is_refused_by_name_when_loaded():
    with pytest.raises(RunError, match=r"^t\.mod:5:1: TriggL is not modelled"):
        load(mod('TPWrite "a";\nTriggL p, v100, trigg, fine, tool0;'), "t.mod")
    with pytest.raises(RunError, match=r"^t\.mod:4:1: unknown routine DoTheThing"):
        load(mod("DoTheThing;"), "t.mod")


def test_the_user_modules_registers_and_clock_need_no_declaration():
    body = 'reg1 := 2;\nIncr reg1;\nClkStart clock1;\nWaitTime 0.5;\nTPWrite "" \\Num:=reg1 + ClkRead(clock1) + reg5;'
    program = load(mod(body), "t.mod")
    assert program.run({}).messages == ["3.5"]
    assert program.run({}).messages == ["3.5"]  # VAR data: every run starts from 0


def test_an_undeclared_name_spelt_as_a_signal_is_read_as_one_and_check_warns():
    from codegen.dialects.core.files import SourceFile
    from codegen.dialects.rapid import Rapid

    body = 'IF DI_PART_OK = 1 AND diDoor = 0 TPWrite "ok";'
    assert run(body, signals={"DI_PART_OK": True}).messages == ["ok"]
    found = Rapid.check_files([SourceFile("t.mod", mod(body))])
    assert [(f.line, f.severity, f.code) for f in found] == [(4, "warning", "implicit-signal")] * 2
    with pytest.raises(RunError, match=r"t\.mod:4:\d+: undefined variable done"):
        load(mod('IF done = 1 TPWrite "x";'), "t.mod")


def test_crobt_without_tool_or_wobj_takes_those_of_the_latest_move():
    decls = 'PERS wobjdata table := [FALSE, TRUE, "", [[100, 0, 0], [1, 0, 0, 0]], [[0, 0, 0], [1, 0, 0, 0]]];'
    body = f'MoveL {P400}, v100, fine, tool0 \\WObj:=table;\np := CRobT();\nTPWrite "" \\Num:=p.trans.x + CPos().x;'
    assert run(body, decls + "\nVAR robtarget p;").messages == ["800"]  # 400 in the table's frame, twice
    with pytest.raises(RunError, match=r"t\.mod:4:\d+: CRobT takes \\Tool:= and \\WObj:= before any move"):
        run("p := CRobT();", "VAR robtarget p;")


def test_move_l_do_sets_its_output_when_the_arm_reaches_the_point():
    trace = run(f"MoveL {P0}, v100, fine, tool0;\nMoveLDO {P400}, v100, z10, tool0, doGlue, 1;\nWaitTime 0;")
    (event,) = trace.outputs
    assert (event.name, event.value, event.line) == ("doGlue", True, 5)
    assert event.time == pytest.approx(trace.moves[1].end_time) and len(trace.moves) == 2
