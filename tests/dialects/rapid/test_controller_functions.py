"""RAPID's view of the controller that public programs use: UIMessageBox, OpMode, RunMode, CTime, ExitCycle,
StorePath / RestoPath and ErrRaise."""

from __future__ import annotations

import pytest

from codegen.dialects.core.files import SourceFile
from codegen.dialects.core.values import RunError
from codegen.dialects.rapid import Rapid
from codegen.dialects.rapid.interpreter import load
from codegen.sim.operator import Operator


def mod(body: str, decls: str = "", routines: str = "") -> str:
    return f"MODULE Cell\n{decls}\nPROC main()\n{body}\nENDPROC\n{routines}\nENDMODULE\n"


def run(body: str, decls: str = "", routines: str = "", **kwargs):
    return load(mod(body, decls, routines), "cell.mod").run({}, **kwargs)


def clean(body: str, decls: str = "", routines: str = "") -> bool:
    return [f for f in Rapid.check_files([SourceFile("cell.mod", mod(body, decls, routines))])] == []


ASK = (
    'answer := UIMessageBox(\\Header:="Feeder" \\MsgArray:=["No part", "Try again?"] \\Buttons:=btnOKCancel '
    "\\Icon:=iconWarning);\nIF answer = resOK THEN\n  TPWrite \"again\";\nELSE\n  TPWrite \"stop\";\nENDIF"
)


def test_uimessagebox_shows_its_lines_and_returns_the_button_pressed():
    assert run(ASK, "VAR btnres answer;").messages == ["No part Try again?", "again"]  # the first button at once
    assert run(ASK, "VAR btnres answer;", devices=[Operator(["Cancel"])]).messages == ["No part Try again?", "stop"]
    assert clean(ASK, "VAR btnres answer;")


def test_uimessagebox_with_its_own_buttons_returns_the_buttons_number():
    body = 'n := UIMessageBox(\\Message:="Which?" \\BtnArray:=["Left", "", "Right"]);\nTPWrite "" \\Num:=n;'
    assert run(body, "VAR num n;", devices=[Operator(["Right"])]).messages == ["Which?", "3"]
    with pytest.raises(RunError, match=r"the operator's answer 2 is not one of the buttons \(1 Left, 3 Right\)"):
        run(body, "VAR num n;", devices=[Operator([2])])


def test_the_run_is_in_automatic_and_continuous_mode_and_ctime_counts_its_clock():
    body = 'IF OpMode() = OP_AUTO AND RunMode() = RUN_CONT_CYCLE TPWrite "auto";\nWaitTime 62;\nTPWrite CTime();'
    assert run(body).messages == ["auto", "00:01:02"]
    assert clean(body)


def test_exitcycle_ends_the_run_cleanly_saying_so():
    trace = run('TPWrite "one";\nExitCycle;\nTPWrite "never";')
    assert trace.messages == ["one"]
    assert "ExitCycle" in trace.ended


def test_storepath_and_restopath_pair():
    assert run('StorePath;\nRestoPath;\nStorePath \\KeepSync;\nRestoPath;\nTPWrite "ok";').messages == ["ok"]
    with pytest.raises(RunError, match=r"cell\.mod:4:1: RestoPath without a stored path"):
        run("RestoPath;")


def test_errraise_raises_the_booked_error_for_the_handler_with_its_title():
    decls = "VAR errnum ERR_GRIP := -1;"
    routines = (
        'PROC grip()\n  ErrRaise "ERR_GRIP", 7055, "Gripper", ERRSTR_TASK, "no part", ERRSTR_CONTEXT, ERRSTR_EMPTY;\n'
        'ERROR\n  IF ERRNO = ERR_GRIP THEN\n    TPWrite "handled";\n    TRYNEXT;\n  ENDIF\nENDPROC'
    )
    body = 'BookErrNo ERR_GRIP;\ngrip;\nTPWrite "after";'
    assert run(body, decls, routines).messages == ["Gripper", "handled", "after"]
    assert clean(body, decls, routines)
