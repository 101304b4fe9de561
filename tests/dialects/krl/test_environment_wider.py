"""The controller's environment beyond what codegen writes: the operating mode's flags, Automatic External's
globals, VARSTATE and its enumeration, STATE_T, a TRIGGER that sets a variable, and P00 refused by name."""

from __future__ import annotations

import pytest

from codegen.dialects.core.values import RunError
from tests.dialects.krl.helpers import run

FRAMES = "$BASE = $NULLFRAME\n$TOOL = $NULLFRAME\n"
HOME = "PTP {A1 0, A2 -90, A3 90, A4 0, A5 0, A6 0}\n"


def test_the_operating_mode_flags_say_automatic_as_mode_op_does():
    body = "MODES[1] = $T1\nMODES[2] = $T2\nMODES[3] = $AUT\nMODES[4] = $EXT\nAUTO = $MODE_OP == #AUT"
    trace = run(body, dat="DECL BOOL MODES[4]\nDECL BOOL AUTO", keep=("MODES", "AUTO"))
    assert trace.kept == {"MODES": [False, False, True, False], "AUTO": True}


def test_the_mode_flags_are_read_only():
    with pytest.raises(RunError, match=r"\$T1 is read-only"):
        run("$T1 = TRUE")


def test_automatic_externals_globals_are_declared_as_in_a_stock_config_dat():
    body = "IF CHECK_HOME THEN\nN = PGNO_TYPE * 100 + PGNO_LENGTH\nENDIF\nMODE = #PGNO_GET"
    trace = run(body, dat="DECL INT N=0\nDECL FUNCT_TYPE MODE", keep=("N", "MODE"))
    assert trace.kept == {"N": 108, "MODE": "#PGNO_GET"}


def test_p00_is_refused_by_what_it_is():
    with pytest.raises(RunError, match=r"P00 \(KUKA's Automatic External module: .*\) is not modelled"):
        run("P00(#EXT_PGNO, #PGNO_GET, NAME[], 0)", dat="DECL CHAR NAME[8]")


def test_varstate_tells_unknown_declared_and_initialized():
    decls = "DECL INT LOCAL_N, LOCAL_M\nDECL VAR_STATE ST\nDECL STATE_T CHANNEL"
    body = (
        "LOCAL_N = 1\nSTATES[1] = VARSTATE(\"LOCAL_N\")\nSTATES[2] = VARSTATE(\"local_m\")\n"
        "STATES[3] = VARSTATE(\"NOWHERE\")\nSTATES[4] = VARSTATE(\"COUNT\")\nSTATES[5] = VARSTATE(\"HALF\")\n"
        "ST = VARSTATE(\"LOCAL_N\")"
    )
    dat = "DECL VAR_STATE STATES[5]\nDECL INT COUNT=3\nDECL FRAME HALF={X 1.0}"
    trace = run(body, decls, dat, keep=("STATES",))
    assert trace.kept == {"STATES": ["#INITIALIZED", "#DECLARED", "#UNKNOWN", "#INITIALIZED", "#DECLARED"]}


def test_a_trigger_sets_a_variable_at_its_motion():
    # the interpreter sets it when it plans the motion (a read in the advance run sees it early: not modelled)
    body = FRAMES + HOME + "TRIGGER WHEN DISTANCE=1 DELAY=0 DO N = N + 5\nPTP {A1 10, A2 -90, A3 90, A4 0, A5 0, A6 0}"
    trace = run(body + "\nWAIT SEC 0\nAFTER = N", dat="DECL INT N=1\nDECL INT AFTER=-1", keep=("AFTER",))
    assert trace.kept == {"AFTER": 6}


def test_numbered_data_nobody_set_are_a_fresh_controllers_with_a_warning_naming_each_entry():
    body = FRAMES + "$BASE = BASE_DATA[4]\n$LOAD = LOAD_DATA[2]\nB_X = $BASE.X\nMASS = $LOAD.M"
    trace = run(body, dat="DECL REAL B_X=9\nDECL REAL MASS=9", keep=("B_X", "MASS"))
    assert trace.kept == {"B_X": 0.0, "MASS": -1.0}
    assert [w.split(" is not set")[0] for w in trace.warnings] == ["BASE_DATA[4]", "LOAD_DATA[2]"]


def test_an_entry_the_program_sets_gives_no_warning():
    body = FRAMES + "TOOL_DATA[3] = {X 0, Y 0, Z 120, A 0, B 0, C 0}\n$TOOL = TOOL_DATA[3]\nTOOL_Z = $TOOL.Z"
    trace = run(body, dat="DECL REAL TOOL_Z=0", keep=("TOOL_Z",))
    assert trace.kept == {"TOOL_Z": 120.0}
    assert trace.warnings == []
