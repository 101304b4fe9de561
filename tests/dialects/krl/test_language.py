"""The KRL language of the KSS 8 manuals' syntax chapters: each construct people write runs (or is refused by name)."""

from __future__ import annotations

import pytest

from codegen.dialects.core.values import RunError
from codegen.robot.arms import find_arm

from .helpers import INI, KRL, files, program, run

POSE = "{X 500,Y 0,Z 600,A 0,B 90,C 0,S 2,T 35}"


def kept(body: str, names: str, decls: str = "", dat: str = "", routines: str = "", **options) -> dict:
    trace = program(body, decls, dat, routines).run({}, keep=tuple(names.split()), **options)
    return trace.kept


def test_ext_declarations_in_a_data_list_and_a_routine():
    """EXT BAS (BAS_COMMAND :IN, REAL :IN) in every teach-pendant .dat; EXT / EXTFCT in a routine's declarations."""
    decls = "EXT BAS (BAS_COMMAND :IN,REAL :IN )\nEXTFCT REAL TWICE (REAL :IN)"
    routines = "DEFFCT REAL TWICE(V:IN)\nDECL REAL V\nRETURN 2 * V\nENDFCT\n"
    assert kept("X = TWICE(2.5)", "X", dat="DECL REAL X", decls=decls, routines=routines) == {"X": 5.0}


def test_an_ext_routine_defined_nowhere_is_refused_when_loaded():
    with pytest.raises(RunError, match=r"t\.src:\d+:\d+: unknown routine GONE: declared EXT"):
        program("GONE(1)", "EXT GONE (INT :IN)")


def test_based_integers_and_multi_dimensional_arrays():
    body = "A[2,3] = 'H1F'\nB[1,2,2] = 'B101'\nN = A[2,3] + B[1,2,2]\nTXT[2,] = \"two\"\nW[] = TXT[2,]"
    dat = "DECL INT A[3,4]\nDECL INT B[2,2,2]\nDECL INT N\nDECL CHAR TXT[3,8]\nDECL CHAR W[8]"
    assert kept(body, "N W", dat=dat) == {"N": 31 + 5, "W": "two"}


def test_an_array_has_up_to_three_dimensions():
    with pytest.raises(RunError, match="up to 3 dimensions"):
        program("", dat="DECL INT A[2,2,2,2]")


def test_goto_jumps_forward_backward_and_out_of_a_block():
    body = "N = 0\nAGAIN:\nN = N + 1\nIF N < 5 THEN\nGOTO AGAIN\nENDIF\nWHILE TRUE\nGOTO OUT\nENDWHILE\nN = 99\nOUT:\n"
    assert kept(body, "N", dat="DECL INT N") == {"N": 5}


def test_goto_into_a_block_is_refused():
    body = "GOTO INSIDE\nIF TRUE THEN\nINSIDE:\nENDIF"
    with pytest.raises(RunError, match=r"t\.src:3:1: GOTO INSIDE: no such label"):
        program(body)


def test_a_goto_loop_counts_steps():
    with pytest.raises(RunError, match="step limit"):
        run("TOP:\nGOTO TOP", step_limit=500)


def test_enum_and_struc_declared_in_a_data_list():
    dat = (
        "ENUM COLOR_T RED,GREEN,BLUE\nSTRUC PART_T INT COUNT,REAL WEIGHT,COLOR_T COLOR,CHAR NAME[12]\n"
        'DECL PART_T PART={COUNT 2,WEIGHT 1.5,COLOR #GREEN,NAME[] "bolt"}\nDECL INT N\nDECL BOOL IS_GREEN'
    )
    body = "PART.COUNT = PART.COUNT + 1\nN = PART.COUNT\nIS_GREEN = PART.COLOR == #GREEN"
    assert kept(body, "N IS_GREEN", dat=dat) == {"N": 3, "IS_GREEN": True}
    with pytest.raises(RunError, match=r"#PINK is not a value of COLOR_T"):
        program("PART.COLOR = #PINK", dat=dat).run({})


def test_a_literal_of_another_type_is_refused_before_the_program_runs():
    """DECL INT N = "abc" in a .dat: one message naming the file and line (no traceback)."""
    with pytest.raises(RunError, match=r"^t\.dat:3:\d+: type error: cannot assign CHAR to INT$"):
        program("", dat='DECL INT N = "abc"')
    with pytest.raises(RunError, match=r"^t\.src:3:1: type error: cannot assign CHAR to INT$"):
        program('I = "abc"', "DECL INT I")


@pytest.mark.parametrize(
    "value",
    ["N", "N + 1", "-N", "F.X", "A[1]", "SQRT(2.0)", "LIMIT"],
    ids=["variable", "expression", "negated", "component", "element", "call", "named constant"],
)
def test_an_aggregate_takes_constants_only(value):
    """{X N} is refused when the module loads (KSS compiles it so), naming the line; constants pass."""
    decls = "DECL INT N\nDECL FRAME F\nDECL REAL A[2]"
    with pytest.raises(RunError, match=r"^t\.src:\d+:\d+: X in an aggregate is a variable or an expression"):
        program(f"F = {{X {value}, Y 0}}", decls, dat="DECL CONST REAL LIMIT = 2.0")
    dat = "STRUC PAIR_T FRAME F, INT K, CHAR T[4], BOOL B\nDECL PAIR_T P\nDECL INT N\nDECL REAL X"
    body = 'P = {F {X -1.5, Y +2, Z 3E2}, K -4, T[] "ab", B TRUE}\nX = P.F.X\nN = P.K'
    assert kept(body, "N X", dat=dat) == {"N": -4, "X": -1.5}


def test_halt_without_a_message_stops_with_none():
    trace = run("HALT")
    assert trace.halted and trace.halt_message is None and trace.messages == []


def test_ptp_to_axis_values_without_a_type():
    trace = run(INI + "PTP {A1 0, A2 -90, A3 90, A4 0, A5 0, A6 0}\nPTP {A1 10}")
    assert [m.kind for m in trace.moves] == ["joint", "joint"]
    assert list(trace.moves[1].joints) == [10.0, -90.0, 90.0, 0.0, 0.0, 0.0]  # the axes it does not name stay


def test_spline_motions_and_with_apply_to_their_motion_only():
    body = (
        INI + f"SPTP {POSE} WITH $VEL_AXIS[1] = SVEL_JOINT(40.0)\n"
        "SLIN {X 500,Y 100,Z 600,A 0,B 90,C 0} WITH $VEL = SVEL_CP(0.3, , LDEFAULT), "
        "$TOOL = {X 0,Y 0,Z 100,A 0,B 0,C 0} C_SPL\nLIN {X 500,Y 100,Z 500,A 0,B 90,C 0}\n"
        "SCIRC {X 500,Y 150,Z 550,A 0,B 90,C 0}, {X 500,Y 200,Z 500,A 0,B 90,C 0}"
    )
    trace = run(body.replace("SCIRC", "$ORI_TYPE = #CONSTANT\n$CIRC_TYPE = #BASE\nSCIRC"))
    first, spline, lin, circ = trace.moves
    assert first.settings["vel_ptp"] == 40.0
    assert spline.settings["vel_cp"] == pytest.approx(0.3) and spline.settings["approx"] == "C_SPL"
    assert lin.settings["vel_cp"] == 2.0  # BAS(#INITMOV)'s DEF_VEL_CP again: WITH held for the SLIN only
    assert spline.tcp2base[2, 3] == pytest.approx(600.0) and lin.tcp2base[2, 3] == pytest.approx(500.0)
    assert circ.settings.get("circ") is True


def test_with_on_a_conventional_motion():
    trace = run(INI + f"PTP {POSE}\nLIN {{X 500,Y 50,Z 600,A 0,B 90,C 0}} WITH $VEL.CP = 0.1, $ACC.CP = 1.0")
    assert trace.moves[1].settings["vel_cp"] == pytest.approx(0.1)
    assert trace.moves[1].settings["acc_cp"] == pytest.approx(1.0)


def test_the_inline_forms_double_approximation():
    """KSS 8.3's LIN inline form writes LIN XP2 C_DIS C_DIS."""
    lines = f"PTP {POSE}\nLIN {{X 500,Y 50,Z 600,A 0,B 90,C 0}} C_DIS C_DIS\nLIN {{X 500,Y 90,Z 600,A 0,B 90,C 0}}"
    trace = run(INI + lines)
    assert [m.settings["approx"] for m in trace.moves] == [None, "C_DIS", None]


def test_relative_motions():
    """LIN_REL {Z -100} shifts along the base's axes, #TOOL along the tool's; PTP_REL {A1 10} adds to an axis."""
    body = INI + f"PTP {POSE}\nLIN_REL {{Z -100}} C_DIS\nSLIN_REL {{X 50}} #TOOL\nPTP_REL {{A1 10}}"
    trace = run(body, arm=find_arm("KR 10 R1100 sixx"))
    down, along_tool, turned = trace.moves[1:]
    assert down.tcp2base[:3, 3].tolist() == pytest.approx([500.0, 0.0, 500.0], abs=1e-3)
    assert along_tool.tcp2base[:3, 3].tolist() == pytest.approx([500.0, 0.0, 450.0], abs=1e-3)  # tool x: down (B 90)
    assert turned.joints[0] == pytest.approx(along_tool.joints[0] + 10.0, abs=1e-3)
    with pytest.raises(RunError, match=r"t\.src:3:1: SCIRC_REL \(a relative motion\) is not modelled"):
        program("SCIRC_REL {X 10}, {X 20}")
    with pytest.raises(RunError, match="a relative rotation"):
        run(INI + f"PTP {POSE}\nLIN_REL {{A 10}}")


def test_trigger_switches_an_output_at_the_end_and_on_the_path():
    body = (
        INI + f"PTP {POSE}\n$VEL.CP = 0.1\n"
        "TRIGGER WHEN DISTANCE=1 DELAY=-200 DO $OUT[3]=TRUE PRIO=-1\n"
        "TRIGGER WHEN PATH=-20 DELAY=0 DO GRIP=TRUE\n"
        "LIN {X 500,Y 100,Z 600,A 0,B 90,C 0}\nWAIT SEC 0"
    )
    trace = run(body, dat="SIGNAL GRIP $OUT[7]")
    lin = trace.moves[1]
    by_name = {o.name: o for o in trace.outputs}
    assert by_name["$OUT[3]"].time == pytest.approx(lin.end_time - 0.2) and by_name["$OUT[3]"].moving
    # 20 mm before, at 0.1 m/s, and the LIN's deceleration ramp at $ACC.CP 2.3 m/s2 (BAS(#INITMOV)): v / 2a more
    assert by_name["$OUT[7]"].time == pytest.approx(lin.end_time - 0.02 / 0.1 - 0.1 / (2 * 2.3))
    assert by_name["$OUT[7]"].tcp2base[1, 3] == pytest.approx(80.0)


def test_trigger_calls_a_subprogram_at_its_switching_point():
    body = (
        INI + f"PTP {POSE}\n$VEL.CP = 0.1\nTRIGGER WHEN DISTANCE=0 DELAY=50 DO GLUE_ON(3) PRIO=-1\n"
        "LIN {X 500,Y 100,Z 600,A 0,B 90,C 0}\nWAIT SEC 0"
    )
    routines = "DEF GLUE_ON(N:IN)\nDECL INT N\n$OUT[N] = TRUE\nCALLS = CALLS + 1\nEND\n"
    trace = program(body, dat="DECL INT CALLS=0", routines=routines).run({}, keep=("CALLS",))
    lin, [glue] = trace.moves[1], trace.outputs
    assert (glue.name, glue.moving, trace.kept) == ("$OUT[3]", True, {"CALLS": 1})
    # 100 mm at 0.1 m/s with its ramps at 2.3 m/s2: it starts 1 s + v / a before its end
    assert glue.time == pytest.approx(lin.end_time - 1.0 - 0.1 / 2.3 + 0.05)
    with pytest.raises(RunError, match=r"TRIGGER \.\.\. DO GLUE_ON\(\): the interpreter passes constants"):
        program("TRIGGER WHEN DISTANCE=0 DELAY=0 DO GLUE_ON(CALLS) PRIO=-1", dat="DECL INT CALLS=0", routines=routines)


def test_signals_declared_and_undeclared_io_are_named_in_the_trace():
    dat = "SIGNAL LAMP $OUT[12]\nSIGNAL READY $IN[4]\nSIGNAL CODE $OUT[20] TO $OUT[22]"
    body = "IF READY THEN\nLAMP = TRUE\nENDIF\n$OUT[2] = $IN[9]\nCODE = 5"
    trace = program(body, dat=dat).run({}, signals={"$IN[4]": True})
    assert [(o.name, o.value) for o in trace.outputs] == [
        ("$OUT[12]", True),
        ("$OUT[2]", False),
        ("$OUT[20]", True),
        ("$OUT[22]", True),
    ]


def test_an_input_cannot_be_set():
    with pytest.raises(RunError, match=r"\$IN\[n\] is an input"):
        program("$IN[3] = TRUE")


def test_windows_1252_text_is_read():
    from codegen.dialects.core.files import decode_text

    raw = 'DEF T()\n; Greifer schließen, Teil für Station 2\nMsgNotify("Prüfung")\nEND\n'.encode("cp1252")
    text = decode_text(raw, "t.src", KRL.encodings)
    assert KRL.load_files(files(t_src=text)).run({}).messages == ["Prüfung"]


def test_global_routines_and_public_data_of_other_modules():
    main = "DEF CELL()\nCOUNT_PART(2)\nTOTAL = TOTAL + STEP_OF()\nEND\n"
    lib = (
        "DEF LIB()\nEND\nGLOBAL DEF COUNT_PART(N:IN)\nDECL INT N\nTOTAL = TOTAL + N\nHIDDEN = 1\nEND\n"
        "GLOBAL DEFFCT INT STEP_OF()\nRETURN STEP_SIZE\nENDFCT\n"
    )
    lib_dat = "DEFDAT LIB PUBLIC\nDECL GLOBAL INT TOTAL=0\nDECL INT HIDDEN=0\nDECL INT STEP_SIZE=10\nENDDAT\n"
    group = KRL.programs(files(cell_src=main, lib_src=lib, lib_dat=lib_dat, other_src="DEF OTHER()\nEND\n"))
    names = [[f.name for f in g] for g in group]
    assert names == [["cell.src", "lib.src", "lib.dat"], ["other.src", "lib.src", "lib.dat"]]  # two programs, one lib
    assert KRL.load_files(group[0]).run({}, keep=("TOTAL",)).kept == {"TOTAL": 12}
    hidden = main.replace("END\n", "HIDDEN = 2\nEND\n", 1)
    with pytest.raises(RunError, match=r"cell\.src:4:1: undefined variable HIDDEN"):
        KRL.load_files(files(cell_src=hidden, lib_src=lib, lib_dat=lib_dat))
    local = lib.replace("GLOBAL DEF COUNT_PART", "DEF COUNT_PART")
    with pytest.raises(RunError, match=r"cell\.src:2:1: unknown routine COUNT_PART"):
        KRL.load_files(files(cell_src=main, lib_src=local, lib_dat=lib_dat))


def test_two_modules_own_data_of_one_name_apart():
    main = "DEF CELL()\nN = 1\nBUMP()\nEND\n"
    lib = "DEF LIB()\nEND\nGLOBAL DEF BUMP()\nN = N + 100\nEND\n"
    lib_dat = "DEFDAT LIB\nDECL INT N=5\nENDDAT\n"
    program_ = KRL.load_files(
        files(cell_src=main, cell_dat="DEFDAT CELL\nDECL INT N=0\nENDDAT\n", lib_src=lib, lib_dat=lib_dat)
    )
    trace = program_.run({}, keep=("N", "LIB:N"))
    assert trace.kept == {"N": 1, "LIB:N": 105}  # the library's own N, stored apart from the program's


def test_an_interrupt_on_a_signal_name_of_one_input():
    dat = "SIGNAL STOP_BUTTON $IN[5]\nDECL BOOL STOPPED=FALSE"
    routines = "DEF ON_STOP()\nSTOPPED = TRUE\nEND\n"
    body = "INTERRUPT DECL 20 WHEN STOP_BUTTON == TRUE DO ON_STOP()\nINTERRUPT ON 20"
    assert program(body, dat=dat, routines=routines).run({}).halted is False
    with pytest.raises(RunError, match="INTERRUPT DECL: the interpreter models a condition on one input"):
        program(body.replace("STOP_BUTTON == TRUE", "STOP_BUTTON AND $IN[6]"), dat=dat, routines=routines)


@pytest.mark.parametrize(
    ("body", "says"),
    [
        ("R = R[1,2]", r"t\.src:5:5: REAL is not an array$"),
        ("F = F + 1", r"t\.src:5:1: type mismatch \(an operator or an index on values of types it does not take\)$"),
    ],
)
def test_type_mismatches_name_no_python_types(body, says):
    with pytest.raises(RunError, match=says):
        program(f"R = 1.5\nF = {{X 1,Y 2,Z 3,A 0,B 0,C 0}}\n{body}", dat="DECL REAL R\nDECL FRAME F").run({})


def test_another_modules_main_routine_is_called_by_its_name_and_its_local_ones_are_not():
    lib = "DEF LIB(N:IN)\nDECL INT N\nHELPER()\nTOTAL = TOTAL + N\nEND\nDEF HELPER()\nTOTAL = TOTAL + 100\nEND\n"
    lib_dat = "DEFDAT LIB PUBLIC\nDECL GLOBAL INT TOTAL=0\nENDDAT\n"
    main = "DEF CELL()\nEXT LIB (INT :IN)\nLIB(5)\nEND\n"
    group = KRL.programs(files(cell_src=main, lib_src=lib, lib_dat=lib_dat))[0]
    assert KRL.load_files(group).run({}, keep=("TOTAL",)).kept == {"TOTAL": 105}
    with pytest.raises(RunError, match=r"cell\.src:4:1: unknown routine HELPER"):
        KRL.load_files(files(cell_src=main.replace("LIB(5)", "LIB(5)\nHELPER()"), lib_src=lib, lib_dat=lib_dat))


def test_elseif_is_named_as_not_krl_with_its_line():
    body = "N = 1\nIF N == 1 THEN\nN = 2\n  ELSEIF N == 2 THEN\nN = 3\nENDIF"
    with pytest.raises(RunError, match=r"^t\.src:6:3: syntax error: KRL has no ELSEIF: nest an IF .* or use SWITCH$"):
        program(body, decls="DECL INT N")
