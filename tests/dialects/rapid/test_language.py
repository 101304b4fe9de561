"""RAPID language constructs of the manual's syntax chapters: RECORD, ALIAS, GOTO, optional parameters, arrays..."""

from __future__ import annotations

import pytest

from codegen.dialects.core.files import SourceFile
from codegen.dialects.core.values import RunError
from codegen.dialects.rapid import Rapid
from codegen.dialects.rapid.interpreter import load


def mod(body: str, decls: str = "", routines: str = "", name: str = "T") -> str:
    return f"MODULE {name}\n{decls}\nPROC main()\n{body}\nENDPROC\n{routines}\nENDMODULE\n"


def messages(body: str, decls: str = "", routines: str = "", **kwargs) -> list[str]:
    return load(mod(body, decls, routines), "t.mod").run({}, **kwargs).messages


def test_record_types_are_declared_aggregated_read_and_written():
    decls = (
        "RECORD part\n  string name;\n  pos offset;\n  num count;\nENDRECORD\n"
        'VAR part p := ["bolt", [1, 2, 3], 4];\nVAR part q;'
    )
    body = 'q := p;\nq.offset.y := 20;\nq.count := q.count + 1;\nTPWrite q.name + " " \\Num:=q.offset.y + q.count;'
    body += '\nTPWrite "" \\Num:=p.offset.y;\nTPWrite "[" + q.name + "]" \\Num:=Dim(parts, 1);'
    decls += '\nCONST part parts{2} := [["a", [0, 0, 0], 1], ["b", [0, 0, 0], 2]];'
    assert messages(body, decls) == ["bolt 25", "2", "[bolt]2"]


def test_a_record_aggregate_of_the_wrong_size_is_refused():
    decls = "RECORD part\n  string name;\n  num count;\nENDRECORD\nVAR part p;"
    with pytest.raises(RunError, match=r"t\.mod:\d+:\d+: part has 2 components, got 3"):
        messages('p := ["a", 1, 2];', decls)


def test_alias_names_a_type():
    decls = "ALIAS num length;\nVAR length l := 2.5;"
    assert messages('l := l * 2;\nTPWrite "" \\Num:=l;', decls) == ["5"]


@pytest.mark.parametrize(
    ("decls", "message"),
    [
        ("VAR robtargt p;", r"t\.mod:2:5: unknown data type robtargt"),
        ("VAR triggdata t;", r"t\.mod:2:5: data type triggdata is not modelled"),
        ("PERS partdata p;", r"t\.mod:2:6: unknown data type partdata"),
    ],
)
def test_an_unknown_data_type_is_refused_when_the_program_is_loaded(decls, message):
    with pytest.raises(RunError, match=message):
        load(mod("", decls), "t.mod")


def test_goto_jumps_backwards_forwards_and_out_of_a_compound_statement():
    body = (
        "n := 0;\nagain:\nIncr n;\nIF n < 3 GOTO again;\n"
        "WHILE TRUE DO\n  IF n >= 3 THEN\n    GOTO out;\n  ENDIF\nENDWHILE\n"
        'TPWrite "never";\nout:\nTPWrite "n " \\Num:=n;'
    )
    assert messages(body, "VAR num n;") == ["n 3"]


def test_a_goto_into_a_compound_statement_or_to_no_label_is_refused():
    with pytest.raises(RunError, match=r"t\.mod:4:1: GOTO inside: no label inside"):
        load(mod("GOTO inside;\nIF TRUE THEN\ninside:\nENDIF"), "t.mod")
    with pytest.raises(RunError, match="GOTO nowhere: no label nowhere"):
        load(mod("GOTO nowhere;"), "t.mod")


def test_an_endless_goto_loop_ends_at_the_step_limit():
    with pytest.raises(RunError, match="step limit 50 reached"):
        load(mod("top:\nGOTO top;"), "t.mod").run({}, step_limit=50)


OPTIONAL = """
PROC show(num a \\num b | \\switch none, \\string unit)
  IF Present(b) THEN
    TPWrite "b " \\Num:=a + b;
  ELSEIF Present(none) THEN
    TPWrite "none";
  ELSE
    TPWrite "a " \\Num:=a;
  ENDIF
  IF Present(unit) TPWrite unit;
ENDPROC
PROC pass(\\num b)
  show 1 \\b?b;
ENDPROC
"""


def test_optional_parameters_switches_present_and_conditional_arguments():
    body = 'show 1;\nshow 1 \\b:=2;\nshow 1 \\none;\nshow 1, \\unit:="mm";\npass;\npass \\b:=5;'
    assert messages(body, routines=OPTIONAL) == ["a 1", "b 3", "none", "a 1", "mm", "a 1", "b 6"]


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ("show 1 \\b:=2 \\none;", r"\\B and \\None are alternatives"),
        ("show 1 \\c:=2;", r"show has no optional parameter \\C"),
        ("show;", "show takes 1 arguments, got 0"),
    ],
)
def test_wrong_optional_arguments_are_refused_when_loaded(body, message):
    with pytest.raises(RunError, match=message):
        load(mod(body, routines=OPTIONAL), "t.mod")


def test_reading_an_optional_parameter_that_is_not_present_is_an_error_a_handler_may_take():
    routines = "FUNC num twice(\\num x)\n  RETURN 2 * x;\nERROR\n  RETURN -1;\nENDFUNC"
    assert messages('TPWrite "" \\Num:=twice(\\x:=4);\nTPWrite "" \\Num:=twice();', routines=routines) == ["8", "-1"]


def test_two_dimensional_arrays():
    decls = "VAR num grid{2,3} := [[1, 2, 3], [4, 5, 6]];"
    body = 'grid{2,3} := grid{1,2} * 10;\nTPWrite "" \\Num:=grid{2,3} + Dim(grid, 2);\nTPWrite "" \\Num:=grid{2,1};'
    assert messages(body, decls) == ["23", "4"]
    with pytest.raises(RunError, match=r"t\.mod:4:1: index 3 out of range"):
        messages("grid{3,1} := 0;", decls)
    with pytest.raises(RunError, match=r"t\.mod:4:\d+: index 4 out of range 1\.\.3"):
        messages('TPWrite "" \\Num:=grid{1,4};', decls)


def test_test_case_default():
    routines = (
        'PROC pick(num n)\n  TEST n\n  CASE 1, 2:\n    TPWrite "low";\n  CASE 3:\n    TPWrite "three";\n'
        '  DEFAULT:\n    TPWrite "other";\n  ENDTEST\nENDPROC'
    )
    assert messages("pick 2;\npick 3;\npick 9;", routines=routines) == ["low", "three", "other"]


def test_late_binding_calls_the_procedure_a_string_names():
    routines = 'PROC station1(num n)\n  TPWrite "one " \\Num:=n;\nENDPROC\n'
    routines += 'PROC station2(num n)\n  TPWrite "two";\nENDPROC'
    body = 'FOR i FROM 1 TO 2 DO\n  %"station" + NumToStr(i, 0)% i;\nENDFOR'
    assert messages(body, routines=routines) == ["one 1", "two"]
    handled = '%"station9"% 1;\nERROR\n  IF ERRNO = ERR_REFUNKPRC TPWrite "no such station";\n  TRYNEXT;'
    assert messages(handled, routines=routines) == ["no such station"]


def test_string_literals_with_character_codes_and_doubled_quotes():
    assert messages('TPWrite "A\\41\\\\B""" + "\\e4";') == ['AA\\B"ä']


def test_module_attributes_and_backward_handlers_are_accepted_undo_is_refused():
    text = 'MODULE T(SYSMODULE, NOSTEPIN, VIEWONLY)\nPROC main()\n  TPWrite "x";\n'
    text += 'BACKWARD\n  TPWrite "back";\nENDPROC\nENDMODULE\n'
    assert load(text, "t.mod").run({}).messages == ["x"]
    undo = text.replace("BACKWARD", "UNDO")
    with pytest.raises(RunError, match=r"t\.mod:4:1: an UNDO handler is not modelled"):
        load(undo, "t.mod")


def test_a_for_counter_is_the_loops_own_and_unknown_after_it():
    with pytest.raises(RunError, match=r"t\.mod:6:18: undefined variable i"):
        load(mod('FOR i FROM 1 TO 2 DO\nENDFOR\nTPWrite "" \\Num:=i;'), "t.mod")


def test_an_assignment_to_a_constant_is_refused():
    with pytest.raises(RunError, match=r"t\.mod:4:1: k is a CONST"):
        load(mod("k := 2;", "CONST num k := 1;"), "t.mod")


# --- a task of several modules ------------------------------------------------------------------------


def task(*modules: tuple[str, str]):
    return Rapid.load_files([SourceFile(name, text) for name, text in modules])


def test_routines_data_and_records_of_another_module_and_local_names_per_module():
    main = (
        "MODULE Main\n  LOCAL VAR num n := 1;\n  PROC main()\n    VAR item it;\n    it := first;\n"
        "    helper;\n    TPWrite it.label \\Num:=n + shared;\n  ENDPROC\nENDMODULE\n"
    )
    lib = (
        'MODULE Lib(SYSMODULE)\n  RECORD item\n    string label;\n  ENDRECORD\n  CONST item first := ["first "];\n'
        "  PERS num shared := 10;\n  LOCAL VAR num n := 100;\n  PROC helper()\n    n := n + 1;\n"
        '    TPWrite "lib " \\Num:=n;\n  ENDPROC\nENDMODULE\n'
    )
    assert task(("main.mod", main), ("lib.sys", lib)).run({}).messages == ["lib 101", "first 11"]


def test_a_local_routine_is_not_seen_from_another_module():
    main = "MODULE Main\n  PROC main()\n    hidden;\n  ENDPROC\nENDMODULE\n"
    lib = "MODULE Lib\n  LOCAL PROC hidden()\n  ENDPROC\nENDMODULE\n"
    with pytest.raises(RunError, match=r"main\.mod:3:5: unknown routine hidden"):
        task(("main.mod", main), ("lib.mod", lib))


def test_a_global_name_declared_in_two_modules_is_refused():
    main = "MODULE Main\n  VAR num n;\n  PROC main()\n  ENDPROC\nENDMODULE\n"
    lib = "MODULE Lib\n  PERS num n := 1;\nENDMODULE\n"
    with pytest.raises(RunError, match=r"lib\.mod:2:\d+: n is declared in modules MAIN and LIB"):
        task(("main.mod", main), ("lib.mod", lib))


def test_module_data_may_be_initialised_from_data_of_a_later_module():
    main = "MODULE Main\n  CONST num twice := base * 2;\n  PROC main()\n"
    main += '    TPWrite "" \\Num:=twice;\n  ENDPROC\nENDMODULE\n'
    lib = "MODULE Lib\n  CONST num base := 21;\nENDMODULE\n"
    assert task(("main.mod", main), ("lib.mod", lib)).run({}).messages == ["42"]


def test_a_placeholder_loads_is_an_error_where_it_runs_and_predefined_error_numbers_are_known():
    program = load(mod('TPWrite "a";\n<SMT>'), "t.mod")
    with pytest.raises(RunError, match=r"t\.mod:5:1: <SMT> is a placeholder"):
        program.run({})
    handler = 'x := 1 / 0;\nERROR\n  IF ERRNO = ERR_PATHDIST OR ERRNO = ERR_DIVZERO TPWrite "handled";\n  TRYNEXT;'
    assert messages(handler, "VAR num x;") == ["handled"]


def test_hexadecimal_octal_and_binary_literals():
    assert messages('TPWrite "" \\Num:=0xFF + 0o10 + 0b101;') == ["268"]
    with pytest.raises(RunError, match=r"t\.mod:4:\d+: 0b102 is not a binary number"):
        messages('TPWrite "" \\Num:=0b102;')


def test_alternatives_share_the_backslash_of_the_first_one():
    # RAPID kernel manual, parameter declarations: \switch on | switch off (at most one of them in a call)
    routines = 'PROC grip(\\switch pick | switch place)\n  IF Present(pick) TPWrite "pick";\n'
    routines += '  IF Present(place) TPWrite "place";\nENDPROC'
    assert messages("grip \\pick;\ngrip \\place;\ngrip;", routines=routines) == ["pick", "place"]
    with pytest.raises(RunError, match=r"\\Pick and \\Place are alternatives|\\Place and \\Pick are alternatives"):
        messages("grip \\pick \\place;", routines=routines)
    with pytest.raises(RunError, match=r"only optional parameters \(\\name\) are alternatives"):
        messages("grip 1;", routines="PROC grip(num a | num b)\nENDPROC")


@pytest.mark.parametrize(
    ("param", "decl", "index"),
    [("{*,*}", "{2,3} := [[1, 2, 3], [4, 5, 6]]", "{i,3}"), ("{*,*,*}", "{1,2,2} := [[[1, 2], [3, 6]]]", "{1,i,2}")],
)
def test_open_array_parameters_of_two_and_three_dimensions(param, decl, index):
    routines = f"FUNC num pick(num i, num a{param})\n  RETURN a{index} + Dim(a, 2);\nENDFUNC"
    body = 'TPWrite "" \\Num:=pick(2, grid);'
    assert messages(body, f"VAR num grid{decl};", routines) == ["9" if param == "{*,*}" else "8"]
    source = [SourceFile("t.mod", mod(body, f"VAR num grid{decl};", routines))]
    assert [f.message for f in Rapid.check_files(source)] == []
