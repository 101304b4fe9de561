"""RAPID grammar and interpreter."""

import numpy as np
import pytest
from dialect_base import DialectTests

from codegen.dialects.core.values import RunError
from codegen.dialects.rapid.interpreter import load
from codegen.poses import matrix_from_abb


def mod(body: str, decls: str = "", routines: str = "") -> str:
    return f"MODULE T\n{decls}\nPROC main()\n{body}\nENDPROC\n{routines}\nENDMODULE\n"


def run(body: str, decls: str = "", routines: str = "", **inputs):
    return load(mod(body, decls, routines), "t.mod").run(inputs)


POSE_A = "VAR pose a := [[1, 2, 3], [1, 0, 0, 0]];\nVAR pose b;"
SHOW_A = 'TPWrite "" \\Num:=a.trans.x;'


class TestRAPID(DialectTests):
    filename = "t.mod"
    COPIES = mod(f'b := a;\nb.trans.x := 5;\n{SHOW_A}\nTPWrite "" \\Num:=b.trans.x;', POSE_A)
    BY_VALUE = mod(f"scratch a;\n{SHOW_A}", POSE_A, "PROC scratch(pose p)\n  p.trans.x := 42;\nENDPROC")
    BY_REFERENCE = mod(f"bump a;\n{SHOW_A}", POSE_A, "PROC bump(INOUT pose p)\n  p.trans.x := 99;\nENDPROC")
    RUNAWAY = mod("WHILE TRUE DO\nENDWHILE")
    HALT = mod(
        'TPWrite "stop here";\nEXIT;\n'
        "MoveL [[0, 0, 0], [1, 0, 0, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]], v100, fine, tool0;"
    )
    # the missing ';' is noticed at the next token, as on the controller
    SYNTAX_ERROR = ("MODULE T\nPROC main()\n  x := 1\nENDPROC\nENDMODULE\n", 4)
    UNDEFINED = ("MODULE T\nVAR num x;\nPROC main()\n  x := y + 1;\nENDPROC\nENDMODULE\n", 4)
    OUT_OF_RANGE = (mod("x := vals{4};", "CONST num vals{3} := [1, 2, 3];\nVAR num x;"), r"index 4 out of range 1\.\.3")
    FLOAT32 = mod('TPWrite "" \\Num:=16777217.0;')
    WAIT = mod('WaitUntil vis_req = 1;\nTPWrite "go";', "VAR num vis_req := 0;")
    WAIT_NAME = "vis_req"

    def load(self, text):
        return load(text, self.filename)


def test_precedence_and_strings():
    trace = run(
        'TPWrite "a"\\Num:=1 + 2 * 3;\nTPWrite "q""uote " + NumToStr(10 / 4, 2);\n'
        'TPWrite "" \\Num:=7 DIV 2;\nTPWrite "" \\Num:=7 MOD 4;'
    )
    assert trace.messages == ["a7", 'q"uote 2.50', "3", "3"]


def test_boolean_logic_and_keyword_case():
    trace = run('if not 1 > 2 AND 2 > 1 then\n  TPWrite "yes";\nelse\n  TPWrite "no";\nENDIF')
    assert trace.messages == ["yes"]


def test_arrays_from_1_functions_test_for():
    routines = (
        "FUNC num total(num a{*})\n  VAR num s := 0;\n  FOR i FROM 1 TO 3 DO\n    s := s + a{i};\n"
        "  ENDFOR\n  RETURN s;\nENDFUNC"
    )
    body = 'TEST total(vals)\nCASE 6:\n  TPWrite "six";\nDEFAULT:\n  TPWrite "other";\nENDTEST'
    assert run(body, "CONST num vals{3} := [1, 2, 3];", routines).messages == ["six"]
    with pytest.raises(RunError, match="index 4 out of range"):
        run("x := vals{4};", "CONST num vals{3} := [1, 2, 3];\nVAR num x;")


def test_pose_functions():
    body = (
        "p := PoseMult([[10, 20, 30], OrientZYX(30, 20, 10)], [[1, 2, 3], OrientZYX(-40, 5, 60)]);\n"
        "t := [p.trans, NOrient(p.rot), [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]];\n"
        "MoveL t, v100, fine, tool0;\n"
        "q := PoseMult(PoseInv(p), p);\n"
        "v := PoseVect([[1, 0, 0], OrientZYX(90, 0, 0)], [1, 0, 0]);\n"
        'TPWrite ""\\Num:=Round(EulerZYX(\\Z, OrientZYX(30, 20, 10)));\n'
        'TPWrite ""\\Num:=q.trans.x + v.y;'
    )
    from codegen.poses import matrix_from_xyzabc

    trace = run(
        body.replace("Round(", "(").replace("))));", ")));"), "VAR pose p;\nVAR pose q;\nVAR pos v;\nVAR robtarget t;"
    )
    expected = matrix_from_xyzabc((10, 20, 30, 30, 20, 10)) @ matrix_from_xyzabc((1, 2, 3, -40, 5, 60))
    assert np.allclose(trace.moves[0].tcp2base, expected, atol=1e-3)
    assert trace.messages[0] == "30"
    assert abs(float(trace.messages[1]) - 1.0) < 1e-4  # q is identity, v = (1, 1, 0)


def test_unnormalised_quaternion_is_rejected():
    with pytest.raises(RunError, match="not normalised"):
        run("MoveJ [[0, 0, 0], [0.9, 0, 0, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]], v100, z10, tool0;")


def test_robtarget_matrix():
    target = "[[1, 2, 3], [0.5, 0.5, 0.5, 0.5], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]]"
    trace = run(f"MoveJ {target}, v100, z10, tool0;")
    assert np.allclose(trace.moves[0].tcp2base, matrix_from_abb((1, 2, 3, 0.5, 0.5, 0.5, 0.5)))


def test_values_are_copied_and_inout_writes_back():
    decls = "VAR pose a := [[1, 2, 3], [1, 0, 0, 0]];\nVAR pose b;\nVAR num u{3} := [1, 2, 3];\nVAR num w{3};"
    routines = (
        "PROC bump(INOUT pose p)\n  p.trans.x := 99;\nENDPROC\n"
        "PROC scratch(pose p, num k{*})\n  p.trans.x := 42;\n  k{1} := 42;\nENDPROC"
    )
    body = (
        "b := a;\nb.trans.x := 5;\nw := u;\nw{2} := 7;\nscratch a, u;\n"
        'TPWrite "" \\Num:=a.trans.x;\nTPWrite "" \\Num:=b.trans.x;\nTPWrite "" \\Num:=u{1};\n'
        'TPWrite "" \\Num:=u{2};\nTPWrite "" \\Num:=w{2};\nbump a;\nTPWrite "" \\Num:=a.trans.x;\n'
        'TPWrite "" \\Num:=b.trans.x;'
    )
    text = f"MODULE T\n{decls}\nPROC main()\n{body}\nENDPROC\n{routines}\nENDMODULE\n"
    program = load(text, "t.mod")
    expected = ["1", "5", "1", "2", "7", "99", "5"]
    assert program.run({}).messages == expected
    assert program.run({}).messages == expected  # a run never changes the next run's start


def test_store_into_a_nested_element_evaluates_its_index_once():
    decls = "VAR num calls := 0;\nVAR pose pa{2};"
    routines = "FUNC num nxt()\n  calls := calls + 1;\n  RETURN 2;\nENDFUNC"
    body = (
        'pa{nxt()}.trans.x := 5;\nTPWrite "" \\Num:=calls;\nTPWrite "" \\Num:=pa{2}.trans.x;\n'
        'TPWrite "" \\Num:=pa{1}.trans.x;'
    )
    assert run(body, decls, routines).messages == ["1", "5", "0"]


def test_syntax_error_says_what_was_found_and_expected():
    with pytest.raises(RunError, match=r"t.mod:4:1: syntax error at 'ENDPROC', expected one of .*';'"):
        load("MODULE T\nPROC main()\n  x := 1\nENDPROC\nENDMODULE\n", "t.mod")


def test_exit_halts_and_assignment_to_undeclared_fails():
    trace = run('TPWrite "bye";\nEXIT;\nTPWrite "never";')
    assert trace.halted and trace.halt_message == "bye"
    with pytest.raises(RunError, match="undeclared variable"):
        run("zz := 1;")


def test_for_counter_is_the_loops_own_count():
    body = 'FOR i FROM 3 TO 1 STEP -1 DO\n  TPWrite "" \\Num:=i;\nENDFOR'
    assert run(body).messages == ["3", "2", "1"]
    with pytest.raises(RunError, match="FOR with STEP 0"):
        run("FOR i FROM 1 TO 2 STEP 0 DO\nENDFOR")


def test_stop_pauses_and_the_program_goes_on_after_the_restart():
    trace = load(mod('TPWrite "stop here";\nStop;\nTPWrite "after the restart";'), "t.mod").run()
    assert trace.halted and trace.halt_message == "stop here"
    assert trace.messages == ["stop here", "after the restart"]
