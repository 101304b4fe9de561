"""KRL grammar and interpreter."""

import numpy as np
import pytest
from dialect_base import DialectTests

from codegen.dialects.core.values import RunError
from codegen.dialects.krl.interpreter import load
from codegen.poses import matrix_from_xyzabc

DAT = """DEFDAT T PUBLIC
DECL GLOBAL INT VIS_STATION=0
DECL REAL R=0.0
DECL KRLMSG_T MSG={MODUL[] "T",NR 1,MSG_TXT[] " "}
DECL KRLMSGPAR_T PAR[3]
DECL KRLMSGOPT_T OPT={VL_STOP TRUE,CLEAR_P_RESET TRUE,CLEAR_P_SAW FALSE,LOG_TO_DB FALSE}
DECL INT H=0
ENDDAT
"""


def show(kind: str, var: str) -> str:
    """KRL lines that put one INT or REAL variable into a notification message."""
    return (
        f"PAR[1] = {{PAR_TYPE #VALUE}}\nPAR[1].PAR_{kind} = {var}\n"
        'MSG.MSG_TXT[] = "%1"\nH = SET_KRLMSG(#NOTIFY, MSG, PAR[], OPT)'
    )


def src(body: str, decls: str = "", routines: str = "") -> str:
    return f"&ACCESS RVP\nDEF T()\n{decls}\n{body}\nEND\n{routines}"


def run(body: str, decls: str = "", **inputs):
    return load(src(body, decls), "t.src", DAT).run(inputs)


def say_text(text: str) -> str:
    """KRL lines that put a fixed text into a notification message."""
    return f'MSG.MSG_TXT[] = "{text}"\nH = SET_KRLMSG(#NOTIFY, MSG, PAR[], OPT)'


A_FRAME = "DECL FRAME A, B\nA = {X 1, Y 2, Z 3, A 0, B 0, C 0}"


class TestKRL(DialectTests):
    filename = "t.src"
    COPIES = src(f"B = A\nB.X = 5\nR = A.X\n{show('REAL', 'R')}\nR = B.X\n{show('REAL', 'R')}", A_FRAME)
    BY_VALUE = src(
        f"SCRATCH(A)\nR = A.X\n{show('REAL', 'R')}", A_FRAME, "DEF SCRATCH(F:IN)\nDECL FRAME F\nF.X = 42\nEND\n"
    )
    BY_REFERENCE = src(
        f"BUMP(A)\nR = A.X\n{show('REAL', 'R')}", A_FRAME, "DEF BUMP(F:OUT)\nDECL FRAME F\nF.X = 99\nEND\n"
    )
    RUNAWAY = src("LOOP\nENDLOOP")
    halt_resumes = True
    HALT = src(
        'MSG.MSG_TXT[] = "stop here"\nH = SET_KRLMSG(#QUIT, MSG, PAR[], OPT)\nHALT\nPTP {X 0,Y 0,Z 0,A 0,B 0,C 0}'
    )
    SYNTAX_ERROR = ("DEF T()\nDECL INT I\nI = 1\nIF I > 0\nENDIF\nEND\n", 4)
    UNDEFINED = ("DEF T()\nR = Q + 1\nEND\n", 2)
    OUT_OF_RANGE = (src("R = A[4]", "DECL REAL A[3]"), r"index 4 out of range 1\.\.3")
    FLOAT32 = src(f"R = 16777217.0\n{show('REAL', 'R')}")
    WAIT = src(f"WAIT FOR VIS_STATION == 1\n{say_text('go')}")
    WAIT_NAME = "VIS_STATION"

    def load(self, text):
        return load(text, self.filename, DAT)


def say(expr: str, decl: str = "DECL REAL V") -> str:
    trace = run(
        f"V = {expr}\nPAR[1] = {{PAR_TYPE #VALUE}}\nPAR[1].PAR_{'INT' if 'INT' in decl else 'REAL'} = V\n"
        f'MSG.MSG_TXT[] = "%1"\nH = SET_KRLMSG(#NOTIFY, MSG, PAR[], OPT)',
        decl,
    )
    return trace.messages[0]


def test_arithmetic_precedence():
    assert say("1 + 2 * 3") == "7"
    assert say("(1 + 2) * 3") == "9"
    assert say("7 / 2", "DECL INT V") == "3"  # INT / INT is an INT
    assert say("7.0 / 2") == "3.5"


def test_comparison_binds_last_and_keywords_ignore_case():
    body = "b = NOT (1 > 2) and (2 > 1)\nif b then\nR = 1.0\nelse\nR = 2.0\nendif\n" + show("REAL", "R")
    assert run(body, "DECL BOOL B").messages == ["1"]


def test_arrays_start_at_1_and_loops():
    body = (
        "FOR I = 1 TO 3\nA[I] = I * 2\nENDFOR\nS = 0\nI = 1\nWHILE I <= 3\nS = S + A[I]\nI = I + 1\n"
        "ENDWHILE\n" + show("INT", "S")
    )
    assert run(body, "DECL INT A[3], I, S").messages == ["12"]
    with pytest.raises(RunError, match="index 0 out of range"):
        run("A[0] = 1", "DECL INT A[3]")


def test_switch_and_real_is_float32():
    body = "SWITCH 2\nCASE 1\nR = 1.0\nCASE 2, 3\nR = 16777217.0\nDEFAULT\nR = 0.0\nENDSWITCH\n" + show("REAL", "R")
    assert run(body).messages == ["16777216"]


def test_geometric_operator_and_inv_pos():
    a = (10.0, -20.0, 30.0, 15.0, -25.0, 40.0)
    b = (400.0, 50.0, -60.0, 90.0, 10.0, 180.0)
    body = (
        f"F = {{X {a[0]},Y {a[1]},Z {a[2]},A {a[3]},B {a[4]},C {a[5]}}}\n"
        f"P = {{X {b[0]},Y {b[1]},Z {b[2]},A {b[3]},B {b[4]},C {b[5]},S 2,T 35}}\n"
        "$BASE = $NULLFRAME\nQ = F : P\nLIN Q\nPTP INV_POS(F) : F"
    )
    trace = run(body, "DECL FRAME F\nDECL POS P, Q")
    assert np.allclose(trace.moves[0].tcp2base, matrix_from_xyzabc(a) @ matrix_from_xyzabc(b), atol=2e-3)
    assert np.allclose(trace.moves[1].tcp2base, np.eye(4), atol=2e-3)
    assert [m.kind for m in trace.moves] == ["linear", "joint"]


def test_a_program_starts_in_whatever_base_was_active():
    """$BASE persists between programs: moving without setting it moves in the base left active."""
    trace = run("LIN {X 10,Y 0,Z 0,A 0,B 0,C 0}\n$BASE = $NULLFRAME\nLIN {X 10,Y 0,Z 0,A 0,B 0,C 0}")
    assert not np.allclose(trace.moves[0].tcp2base, trace.moves[1].tcp2base, atol=1.0)
    assert np.allclose(trace.moves[1].tcp2base[:3, 3], [10, 0, 0], atol=1e-4)


def test_base_frame_applies_to_moves():
    trace = run("$BASE = {X 100,Y 0,Z 0,A 90,B 0,C 0}\nLIN {X 10,Y 0,Z 0,A 0,B 0,C 0}")
    assert np.allclose(trace.moves[0].tcp2base[:3, 3], [100, 10, 0], atol=1e-4)


def test_trig_in_degrees():
    assert say("SIN(30)") == "0.5"
    assert say("ATAN2(1, 1)") == "45"


def test_uninitialised_value_is_an_error():
    with pytest.raises(RunError, match="has no value"):
        run("R = U + 1", "DECL REAL U")


def test_decl_after_statement_is_rejected():
    with pytest.raises(RunError, match="declarations come first"):
        run("R = 1\nDECL INT LATE")


def test_assignments_in_the_data_list_run_once_before_the_program():
    dat = DAT.replace("ENDDAT", "R = 2.5\nENDDAT")
    text = "&ACCESS RVP\nDEF T()\n" + show("REAL", "R") + "\nR = R + 1\n" + show("REAL", "R") + "\nEND\n"
    program = load(text, "t.src", dat)
    assert program.run({}).messages == ["2.5", "3.5"]
    assert program.run({}).messages == ["2.5", "3.5"]


def test_quit_message_takes_its_parameter():
    trace = run(
        'MSG.MSG_TXT[] = "stop %1"\nPAR[1] = {PAR_TYPE #VALUE}\nPAR[1].PAR_INT = 9\n'
        "H = SET_KRLMSG(#QUIT, MSG, PAR[], OPT)\nHALT"
    )
    assert trace.halted and trace.halt_message == "stop 9"


def test_exit_leaves_loop_repeat_and_for():
    body = (
        "I = 0\nLOOP\nI = I + 1\nIF I == 3 THEN\nEXIT\nENDIF\nENDLOOP\n"
        "REPEAT\nI = I + 1\nIF I == 5 THEN\nEXIT\nENDIF\nUNTIL FALSE\n"
        "FOR J = 1 TO 10\nI = I + 1\nIF J == 2 THEN\nEXIT\nENDIF\nENDFOR\n" + show("INT", "I")
    )
    assert run(body, "DECL INT I, J").messages == ["7"]


def test_for_counts_the_variable_with_step():
    body = "S = 0\nFOR I = 10 TO 1 STEP -3\nS = S * 100 + I\nENDFOR\n" + show("INT", "S")
    assert run(body, "DECL INT I, S").messages == ["10070401"]
    with pytest.raises(RunError, match="FOR with STEP 0"):
        run("FOR I = 1 TO 2 STEP 0\nENDFOR", "DECL INT I")


STOPMESS = "GLOBAL INTERRUPT DECL 3 WHEN $STOPMESS==TRUE DO IR_STOPM()\nINTERRUPT ON 3"


def test_the_templates_stop_message_interrupt_is_declared_then_switched_on():
    """KUKA's INI fold: interrupt 3 calls KUKA's IR_STOPM on a stop message (no stop messages here)."""
    assert run(f"{STOPMESS}\nINTERRUPT OFF 3\nINTERRUPT ON\n" + say_text("on")).messages == ["on"]


@pytest.mark.parametrize(
    ("body", "says"),
    [
        ("INTERRUPT ON 3", "INTERRUPT ON 3: interrupt 3 is not declared"),
        ("INTERRUPT ON 4\n" + STOPMESS, "interrupt 4 is not declared"),  # at run time, in order
        ("INTERRUPT DECL 0 WHEN $IN[1] DO IR_STOPM()", "the priority must be in 1..128"),
        ("INTERRUPT DECL 5 WHEN $IN[1] DO MISSING()", "no routine MISSING to call"),
        ("INTERRUPT FLIP 3", "expected ON, OFF, ENABLE or DISABLE"),
        ("\n".join(f"INTERRUPT DECL {n} WHEN $IN[1] DO IR_STOPM()" for n in range(1, 34)), "more than 32"),
        (
            "\n".join(f"INTERRUPT DECL {n} WHEN $IN[1] DO IR_STOPM()\nINTERRUPT ON {n}" for n in range(1, 18)),
            "INTERRUPT ON 17: more than 16 interrupts on",
        ),
    ],
)
def test_interrupts_the_controller_refuses(body, says):
    with pytest.raises(RunError, match=says):
        run(body)
