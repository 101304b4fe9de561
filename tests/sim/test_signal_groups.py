"""Groups of digital signals read and written as one number: KRL SIGNAL, RAPID GInput/DInput/SetGO."""

from __future__ import annotations

import pytest

from codegen.dialects.core.values import RunError
from codegen.dialects.krl.interpreter import load as load_krl
from codegen.dialects.rapid.interpreter import load as load_rapid

KRL_DAT = """DEFDAT T
DECL INT X = 0
SIGNAL WORD_IN $IN[1001] TO $IN[1016]
SIGNAL WORD_OUT $OUT[1001] TO $OUT[1016]
SIGNAL WIDE $IN[1] TO $IN[32]
ENDDAT
"""


def _krl(body: str):
    return load_krl(f"DEF T()\n{body}END\n", "t.src", KRL_DAT)


def test_a_krl_input_group_reads_its_bits_least_significant_first():
    trace = _krl("  X = WORD_IN\n  IF X <> 41 THEN\n    HALT\n  ENDIF\n").run(
        {}, signals={"$IN[1001]": True, "$IN[1004]": True, "$IN[1006]": True}
    )
    assert not trace.halted  # 1 + 8 + 32


def test_a_krl_output_group_sets_each_output():
    trace = _krl("  WORD_OUT = 5\n").run({})
    assert [(o.name, o.value) for o in trace.outputs] == [("$OUT[1001]", True), ("$OUT[1003]", True)]


def test_a_32_signal_group_is_signed():
    signals = {f"$IN[{n}]": True for n in range(1, 33)}
    trace = _krl("  X = WIDE\n  IF X <> -1 THEN\n    HALT\n  ENDIF\n").run({}, signals=signals)
    assert not trace.halted


def test_a_value_that_does_not_fit_the_group_is_refused():
    with pytest.raises(RunError, match="does not fit 16 signals"):
        _krl("  WORD_OUT = 65536\n").run({})


@pytest.mark.parametrize(
    ("dat", "message"),
    [
        ("SIGNAL G $IN[5] TO $OUT[9]", "expected"),
        ("SIGNAL G $IN[1] TO $IN[40]", "2..32"),
    ],
)
def test_a_bad_signal_declaration_is_refused(dat, message):
    with pytest.raises(Exception, match=message):
        load_krl("DEF T()\nEND\n", "t.src", f"DEFDAT T\n{dat}\nENDDAT\n")


def test_rapid_reads_a_group_and_a_digital_input_and_writes_a_group():
    program = load_rapid(
        "MODULE T\n  PROC main()\n    VAR num x;\n    x := GInput(giWord);\n    SetGO goWord, x + 1;\n"
        '    IF DInput(diStop) = 1 THEN\n      TPWrite "stop";\n    ENDIF\n  ENDPROC\nENDMODULE\n',
        "t.mod",
    )
    trace = program.run({}, signals={"giWord": 41, "diStop": True}, keep=("goWord",))
    assert trace.messages == ["stop"] and trace.kept["goWord"] == 42


def test_rapid_setgo_refuses_a_fraction():
    program = load_rapid("MODULE T\n  PROC main()\n    SetGO goWord, 1.5;\n  ENDPROC\nENDMODULE\n", "t.mod")
    with pytest.raises(RunError, match="not a whole number"):
        program.run({})
