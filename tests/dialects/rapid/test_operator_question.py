"""RAPID's Yes/No question: TPReadFK answered by the run's simulated operator (codegen/sim/operator.py)."""

from __future__ import annotations

import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.dialects.core.files import SourceFile
from codegen.dialects.core.values import RunError
from codegen.dialects.rapid import Rapid
from codegen.dialects.rapid.interpreter import load
from codegen.sim.operator import Operator

ASK = 'TPReadFK answer, "layer 2 box 3 on its place?", "Yes", stEmpty, stEmpty, stEmpty, "No"{options};'
REPLY = 'TEST answer\nCASE 1:\n  TPWrite "placed";\nCASE 5:\n  TPWrite "missing";\nENDTEST'


def module(options: str = "", decls: str = "") -> str:
    body = ASK.format(options=options) + "\n" + REPLY
    return f"MODULE T\nVAR num answer := -1;\n{decls}\nPROC main()\n{body}\nENDPROC\nENDMODULE\n"


def run(answers=None, options: str = "", decls: str = ""):
    devices = [] if answers is None else [Operator(answers)]
    return load(module(options, decls), "t.mod").run({}, devices=devices, keep=("answer",))


@pytest.mark.parametrize(
    ("answer", "key", "said"), [("Yes", 1, "placed"), ("no", 5, "missing"), (1, 1, "placed"), ("5", 5, "missing")]
)
def test_the_operator_presses_a_key_by_its_label_or_number(answer, key, said):
    trace = run([answer])
    assert trace.messages == ["layer 2 box 3 on its place?", said]
    assert trace.kept["answer"] == key


@pytest.mark.parametrize("answer", ["Maybe", 2, "3", 6, True])
def test_an_answer_that_is_no_key_shown_stops_the_run_naming_the_line(answer):
    with pytest.raises(RunError, match=r"^t\.mod:5:1: TPReadFK: the operator's answer .* not one of the keys shown"):
        run([answer])


def test_without_an_operator_or_with_its_answers_used_the_program_waits():
    message = r"^t\.mod:5:1: TPReadFK: the program waits for the operator's answer to 'layer 2 box 3 on its place\?'"
    with pytest.raises(RunError, match=message + r".*codegen run --answer"):
        run()
    twice = module().replace("PROC main()\n", "PROC main()\n" + ASK.format(options="") + "\n")
    with pytest.raises(RunError, match=r"^t\.mod:6:1: TPReadFK: the program waits"):  # the second question
        load(twice, "t.mod").run({}, devices=[Operator(["Yes"])])


def test_max_time_without_an_answer_raises_err_tp_maxtime_or_sets_the_break_flag():
    # no handler: the error stops the program; with \BreakFlag the flag holds ERR_TP_MAXTIME, the answer unchanged
    stopped = run(None, " \\MaxTime:=30")
    assert stopped.halted and stopped.halt_message.startswith("ERR_TP_MAXTIME: t.mod:5:1: TPReadFK \\MaxTime passed")
    trace = run(None, " \\MaxTime:=30 \\BreakFlag:=flag", "VAR errnum flag;")
    assert trace.kept["answer"] == -1 and trace.messages == ["layer 2 box 3 on its place?"]
    assert trace.clock == pytest.approx(30)  # \MaxTime passed
    flagged = module(" \\MaxTime:=30 \\BreakFlag:=flag", "VAR errnum flag;").replace(
        REPLY, 'IF flag = ERR_TP_MAXTIME TPWrite "timed out";'
    )
    assert load(flagged, "t.mod").run({}).messages[-1] == "timed out"
    # answered in time: the key, and the flag 0
    answered = module(" \\MaxTime:=30 \\BreakFlag:=flag", "VAR errnum flag;").replace(REPLY, 'TPWrite "" \\Num:=flag;')
    assert load(answered, "t.mod").run({}, devices=[Operator(["No"])]).messages[-1] == "0"


def test_do_break_is_refused_naming_the_line():
    with pytest.raises(RunError, match=r"^t\.mod:\d+:\d+: TPReadFK \\DOBreak is not modelled here"):
        load(module(" \\DOBreak:=do1", "VAR signaldo do1;"), "t.mod")


class InputAt:
    """A PLC that switches a digital input on at a moment of the run."""

    def __init__(self, name: str, at_s: float) -> None:
        self.name, self.at_s = name, at_s

    def next_time(self, machine):
        return self.at_s if not machine.signals.get(self.name) else None

    def on_wait(self, machine, where: str) -> bool:
        if machine.clock < self.at_s or machine.signals.get(self.name):
            return False
        machine.signals[self.name] = True
        return True


FLAGGED = 'IF flag = ERR_TP_DIBREAK TPWrite "broken";\nIF flag = ERR_TP_MAXTIME TPWrite "timed out";'


def _di_break(devices, signals=None, options=" \\MaxTime:=30 \\DIBreak:=diReset \\BreakFlag:=flag"):
    text = module(options, "VAR errnum flag;").replace(REPLY, FLAGGED)
    return load(text, "t.mod").run({}, devices=devices, signals=signals, keep=("answer",))


def test_di_break_ends_the_dialog_when_its_input_goes_to_1_or_is_1_already():
    late = _di_break([InputAt("diReset", 5.0)])
    assert late.messages[-1] == "broken" and late.clock == pytest.approx(5.0, abs=0.1)
    already = _di_break([Operator(["Yes"])], {"diReset": True})  # the input first: the key is not read
    assert already.messages[-1] == "broken" and already.kept["answer"] == -1
    never = _di_break([])
    assert never.messages[-1] == "timed out" and never.clock == pytest.approx(30)
    answered = _di_break([Operator(["No"])])
    assert answered.kept["answer"] == 5 and answered.messages == ["layer 2 box 3 on its place?"]  # the flag 0
    # no \\BreakFlag: the error stops the program
    stopped = load(module(" \\DIBreak:=diReset"), "t.mod").run({}, signals={"diReset": True})
    assert stopped.halted and stopped.halt_message.startswith("ERR_TP_DIBREAK: t.mod:5:1: TPReadFK \\DIBreak")


def test_a_question_without_a_key_is_refused():
    text = module().replace('"Yes", stEmpty, stEmpty, stEmpty, "No"', "stEmpty, stEmpty, stEmpty, stEmpty, stEmpty")
    with pytest.raises(RunError, match=r"^t\.mod:5:1: TPReadFK: no function key has a text"):
        load(text, "t.mod").run({}, devices=[Operator(["Yes"])])


def test_check_knows_tp_read_fk_and_st_empty():
    assert Rapid.check_files([SourceFile("t.mod", module())]) == []


def test_codegen_run_answer_yes(tmp_path):
    path = tmp_path / "ask.mod"
    path.write_text(module())
    result = CliRunner().invoke(main, ["run", str(path), "--answer", "Yes"])
    assert result.exit_code == 0, result.output
    assert "placed" in result.output and "missing" not in result.output
    result = CliRunner().invoke(main, ["run", str(path)])
    assert result.exit_code != 0 and "waits for the operator's answer" in result.output
