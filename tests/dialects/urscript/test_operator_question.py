"""URScript's Yes/No question: request_boolean_from_primary_client answered by the run's simulated operator."""

from __future__ import annotations

import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.dialects import get_dialect
from codegen.dialects.core.files import CheckOptions, SourceFile
from codegen.dialects.core.values import RunError
from codegen.dialects.urscript.interpreter import load
from codegen.sim.operator import Operator

ASK = """def prog():
  placed = request_boolean_from_primary_client({message})
  if placed:
    textmsg("placed")
  else:
    textmsg("missing")
  end
end
"""
QUESTION = '"layer 2 box 3 on its place?"'


def run(answers=None, message: str = QUESTION):
    devices = [] if answers is None else [Operator(answers)]
    return load(ASK.format(message=message), "t.script").run({}, devices=devices, keep=("placed",))


@pytest.mark.parametrize(
    ("answer", "placed"), [("Yes", True), ("yes", True), ("NO", False), (1, True), (2, False), ("2", False)]
)
def test_the_operator_answers_yes_or_no(answer, placed):
    trace = run([answer])
    assert trace.messages == ["layer 2 box 3 on its place?", "placed" if placed else "missing"]
    assert trace.kept["placed"] is placed


@pytest.mark.parametrize("answer", ["Maybe", "Cancel", 3, 0, True])
def test_an_answer_that_is_no_button_shown_stops_the_run_naming_the_line(answer):
    with pytest.raises(RunError, match=r"^t\.script:2:\d+: request_boolean_from_primary_client: the operator's"):
        run([answer])


def test_without_an_operator_or_with_its_answers_used_the_program_waits():
    message = r"^t\.script:2:\d+: request_boolean_from_primary_client: the program waits for the operator's answer"
    with pytest.raises(RunError, match=message + r" to 'layer 2 box 3 on its place\?'.*codegen run --answer"):
        run()
    again = f"  again = request_boolean_from_primary_client({QUESTION})\n  if placed:"
    twice = ASK.format(message=QUESTION).replace("  if placed:", again)
    with pytest.raises(RunError, match=r"^t\.script:3:\d+: request_boolean_from_primary_client: the program waits"):
        load(twice, "t.script").run({}, devices=[Operator(["Yes"])])


@pytest.mark.parametrize(
    ("message", "refusal"), [('""', "the message cannot be empty"), ("3", "the message is a string")]
)
def test_the_message_is_a_string_not_empty(message, refusal):
    with pytest.raises(RunError, match=rf"^t\.script:2:\d+: request_boolean_from_primary_client: {refusal}"):
        run(["Yes"], message)


def test_an_integer_request_takes_the_operators_typed_number():
    text = ASK.format(message=QUESTION).replace("request_boolean", "request_integer")
    load(text, "t.script")  # loads: the operator types the answer (tests/dialects/urscript/test_more_builtins.py)


def test_check_knows_the_question():
    found = get_dialect("urscript").check_files([SourceFile("t.script", ASK.format(message=QUESTION))], CheckOptions())
    assert [(f.line, f.code) for f in found] == []


def test_codegen_run_answer_yes(tmp_path):
    path = tmp_path / "ask.script"
    path.write_text(ASK.format(message=QUESTION))
    result = CliRunner().invoke(main, ["run", str(path), "--answer", "Yes"])
    assert result.exit_code == 0, result.output
    assert "placed" in result.output and "missing" not in result.output
    result = CliRunner().invoke(main, ["run", str(path), "--answer", "No"])
    assert result.exit_code == 0 and "missing" in result.output
    result = CliRunner().invoke(main, ["run", str(path)])
    assert result.exit_code != 0 and "waits for the operator's answer" in result.output
