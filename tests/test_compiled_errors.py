"""Errors raised inside compiled programs: a RunError naming file:line:column, never a traceback."""

import pytest

from codegen.dialects.core.values import RunError
from codegen.dialects.dtrans.interpreter import load as load_dtrans
from codegen.dialects.krl.interpreter import load as load_krl
from codegen.dialects.rapid.interpreter import load as load_rapid
from codegen.dialects.urscript.interpreter import load as load_ur

RAPID_DECLS = "VAR num x;\nVAR num u{3} := [1, 2, 3];\nVAR pose p;"
RAPID_ROUTINES = (
    "FUNC num f()\n  x := 1;\nENDFUNC\nPROC g(num a)\n  x := a;\nENDPROC\nFUNC pose f2()\n  RETURN 1;\nENDFUNC"
)


def rapid(body: str):
    text = f"MODULE T\n{RAPID_DECLS}\nPROC main()\n{body}\nENDPROC\n{RAPID_ROUTINES}\nENDMODULE\n"
    return load_rapid(text, "t.mod").run({})


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ('x := "a" + 1;', r"t\.mod:6:1: type mismatch"),
        ("x := 1 / 0;", r"t\.mod:6:1: division by zero"),
        ("u{4} := 1;", r"t\.mod:6:1: index 4 out of range"),
        ("x := u{x / 0.0 * 0.0 + 1 / 0};", r"t\.mod:6:1: division by zero"),
        ("p.foo := 1;", r"t\.mod:6:1: no field foo in POSE"),
        ("x := p.foo;", r"t\.mod:6:6: no field foo in POSE"),
        ("x := f();", r"t\.mod:6:6: function f ended without RETURN"),
        ("g 1, 2;", r"t\.mod:6:1: g takes 1 arguments, got 2"),
        ("g 1 \\X:=2;", r"t\.mod:6:1: g has no optional parameters"),
        ("nothere;", r"t\.mod:6:1: unknown routine nothere"),
        ("x := y;", r"t\.mod:6:6: undefined variable y"),
        ('x := "text";', r"t\.mod:6:1: expected a num, got string"),
        ('g "text";', r"t\.mod:6:1: expected a num, got string"),
        ("p := f2();", r"t\.mod:6:6: expected pose, got num"),
    ],
)
def test_rapid_errors_name_the_statement(body, message):
    with pytest.raises(RunError, match=message):
        rapid(body)


KRL_DAT = "DEFDAT T PUBLIC\nDECL INT I=0\nDECL REAL R=0.0\nDECL FRAME F={X 0,Y 0,Z 0,A 0,B 0,C 0}\nENDDAT\n"


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ("I = 1 / 0", r"t\.src:4:1: division by zero"),
        ("R = NOPE", r"t\.src:4:5: undefined variable NOPE"),
        ("F.Q = 1", r"t\.src:4:1: no field Q in FRAME"),
        ("R = F.Q", r"t\.src:4:5: no field Q in FRAME"),
        ("R = F : 1", r"t\.src:4:5: expected FRAME, POS or E6POS"),
        ("DUMMY(1)", r"t\.src:4:1: unknown routine DUMMY"),
    ],
)
def test_krl_errors_name_the_statement(body, message):
    text = f"&ACCESS RVP\nDEF T()\nDECL INT K\n{body}\nEND\n"
    with pytest.raises(RunError, match=message):
        load_krl(text, "t.src", KRL_DAT).run({})


def test_krl_local_without_value_is_an_error_when_read():
    text = "&ACCESS RVP\nDEF T()\nDECL INT K\nI = K + 1\nEND\n"
    with pytest.raises(RunError, match=r"t\.src:4:5: K has no value"):
        load_krl(text, "t.src", KRL_DAT).run({})


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ('x = 1 + "a"', r"t\.script:2:3: type mismatch"),
        ("x = 1 / 0", r"t\.script:2:3: division by zero"),
        ("x = [1, 2]\ny = x[2]", r"t\.script:3:7: index 2 out of range 0\.\.1"),
        ("x = nope", r"t\.script:2:7: undefined variable nope"),
    ],
)
def test_urscript_errors_name_the_statement(body, message):
    text = "def prog():\n" + "".join(f"  {line}\n" for line in body.splitlines()) + "end\n"
    with pytest.raises(RunError, match=message):
        load_ur(text, "t.script").run({})


@pytest.mark.filterwarnings("ignore:overflow:RuntimeWarning", "ignore:invalid value:RuntimeWarning")
@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("Double d = 1.0 / 0.0\n", r"t\.prg:1:1: division by zero"),
        ('Double d = 1.0 + "a"\n', r"t\.prg:1:1: type mismatch"),
        ("Double a[2]\nDouble d = a[5]\n", r"t\.prg:2:12: index 5 out of range 0\.\.1"),
        ('Int i = "a"\n', r"^t\.prg:1:1: expected a number, got str"),
        ("Double a[2]\nDouble n = sqrt(-1.0)\n", r"t\.prg:2:"),
        ("Double a[2]\nDouble f = 1e38 * 1e38\nDouble d = a[f - f]\n", r"t\.prg:2:1: arithmetic overflow"),
    ],
)
def test_dtrans_errors_name_the_statement(text, message):
    with pytest.raises(RunError, match=message):
        load_dtrans(text, "t.prg").run({})


def test_rapid_local_declarations_are_typed():
    text = 'MODULE T\nPROC main()\n  VAR num d;\n  d := "text";\nENDPROC\nENDMODULE\n'
    with pytest.raises(RunError, match=r"t\.mod:4:3: expected a num, got string"):
        load_rapid(text, "t.mod").run({})


def test_long_expressions_compile_and_deep_recursion_is_a_clear_error():
    from support.programs import load_program

    from codegen.controllers import get_target

    terms = " + ".join(["1"] * 200)
    text = f'MODULE T\nVAR num x;\nPROC main()\n  x := {terms};\n  TPWrite "" \\Num:=x;\nENDPROC\nENDMODULE\n'
    assert rapid_program(text).run({}).messages == ["200"]
    deep = " + ".join(["1"] * 2000)
    with pytest.raises(RunError, match=r"t\.mod: statements or expressions nested too deeply"):
        load_program(get_target("abb"), text.replace(terms, deep), "t.mod")
    recursive = "MODULE T\nPROC main()\n  down;\nENDPROC\nPROC down()\n  down;\nENDPROC\nENDMODULE\n"
    with pytest.raises(RunError, match="nested too deeply"):
        rapid_program(recursive).run({}, step_limit=10**7)


def rapid_program(text: str):
    return load_rapid(text, "t.mod")


def test_deeply_nested_blocks_compile():
    body = "".join(f"IF x < {i + 100} THEN\n" for i in range(40)) + 'TPWrite "deep";\n' + "ENDIF\n" * 40
    text = f"MODULE T\nVAR num x := 1;\nPROC main()\n{body}ENDPROC\nENDMODULE\n"
    assert rapid_program(text).run({}).messages == ["deep"]


@pytest.mark.slow
def test_an_elif_chain_of_thousands_compiles():
    """A dispatch over 5,000 stations: Python's compiler nests an elif chain, so a long one continues in
    a function of its own (it failed with "maximum recursion depth exceeded during compilation")."""
    from codegen.dialects.urscript.interpreter import load as load_urscript

    lines = ["def p():", "  station_id = read_input_integer_register(24)"]
    for i in range(1, 5001):
        lines += [f"  {'if' if i == 1 else 'elif'} station_id == {i}:", f'    textmsg("s{i}")']
    lines += ["  else:", '    textmsg("unknown")', "  end", "end", ""]
    program = load_urscript("\n".join(lines), "big.script")
    for station_id, message in ((1, "s1"), (400, "s400"), (401, "s401"), (4999, "s4999"), (5001, "unknown")):
        assert program.run({"input_integer_register_24": station_id}).messages == [message]
    body = "".join(f'  ELSEIF x = {i} THEN\n    TPWrite "r{i}";\n' for i in range(2, 3001))
    head = 'MODULE T\nVAR num x := 2999;\nPROC main()\n  IF x = 1 THEN\n    TPWrite "r1";\n'
    assert rapid_program(f"{head}{body}  ENDIF\nENDPROC\nENDMODULE\n").run({}).messages == ["r2999"]
