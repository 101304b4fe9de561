"""codegen check of KRL: every finding of all files in one report, with file:line, and the field checks."""

from __future__ import annotations

from pathlib import Path

from codegen.dialects.core.files import read_source

from .helpers import INI, KRL, files

PICKCELL = Path(__file__).parent / "programs" / "pickcell"


def check(src: str, dat: str = "DEFDAT T\nENDDAT\n", **more) -> list:
    return KRL.check_files(files(t_src=src, t_dat=dat, **more))


def codes(findings) -> list[tuple[int, str]]:
    return [(f.line, f.code) for f in findings]


def test_every_error_of_every_file_with_its_line():
    src = (
        "DEF T()\n"  # 1
        "DECL INT I\n"  # 2
        'I = "text"\n'  # 3: a type error
        "J = 3\n"  # 4: an undefined name
        "MISSING(1)\n"  # 5: a routine defined nowhere
        "I = = 2\n"  # 6: a syntax error
        "IF I > THEN\n"  # 7: another
        "ENDIF\n"  # 8
        "$WORKSTATE[1] = TRUE\n"  # 9: not modelled
        "END\n"
    )
    dat = 'DEFDAT T\nDECL INT N = "abc"\nDECL REAL R\nR = Q\nENDDAT\n'
    found = check(src, dat)
    assert (3, "type") in codes(found) and (4, "undefined-name") in codes(found)
    assert (5, "undefined-routine") in codes(found) and (6, "syntax") in codes(found) and (7, "syntax") in codes(found)
    assert (9, "unsupported") in codes(found)
    in_dat = [(f.line, f.code) for f in found if f.file == "t.dat"]
    assert (2, "type") in in_dat and (4, "undefined-name") in in_dat
    assert all(f.severity == "unsupported" for f in found if f.code == "unsupported")
    assert not any("Error" in f.message or "NoneType" in f.message for f in found)


def test_a_clean_program_has_no_findings():
    assert check(f"DEF T()\n{INI}PTP XHOME\nEND\n") == []


def test_motion_before_tool_and_base_are_set():
    found = check("DEF T()\nPTP XHOME\nEND\n")
    assert codes(found) == [(2, "motion-before-tool-base")]
    assert "$TOOL and $BASE" in found[0].message
    tool_only = check("DEF T()\n$TOOL = $NULLFRAME\nMOVE()\nEND\nDEF MOVE()\nPTP XHOME\nEND\n")
    assert codes(tool_only) == [(6, "motion-before-tool-base")] and "before $BASE is set" in tool_only[0].message
    fold = "PDAT_ACT=PDEFAULT\nFDAT_ACT=FHOME\nBAS(#PTP_PARAMS,100)\nPTP XHOME\n"
    assert check(f"DEF T()\n{fold}END\n") == []


def test_a_wait_for_an_input_without_a_timeout():
    src = "DEF T()\nWAIT FOR $IN[3]\nWAIT FOR DOOR_CLOSED\nWAIT FOR $IN[4] OR $TIMER_FLAG[1]\nEND\n"
    found = check(src, "DEFDAT T\nSIGNAL DOOR_CLOSED $IN[12]\nENDDAT\n")
    assert codes(found) == [(2, "wait-without-timeout"), (3, "wait-without-timeout")]


def test_names_over_24_characters():
    found = check("DEF T()\nDECL INT PARTS_ON_THE_CONVEYOR_BELT\nEND\n")
    assert codes(found) == [(2, "name-too-long")] and found[0].severity == "error"


def test_an_output_set_in_the_advance_run_and_an_approximation_lost():
    src = (
        f"DEF T()\n{INI}PTP XHOME\nLIN {{X 500,Y 0,Z 500,A 0,B 90,C 0}}\nCONTINUE\n$OUT[4] = TRUE\n"
        "LIN {X 500,Y 0,Z 400,A 0,B 90,C 0} C_DIS\n$OUT[5] = TRUE\nLIN {X 500,Y 0,Z 300,A 0,B 90,C 0}\n"
        "WAIT SEC 0\nCONTINUE\n$OUT[6] = TRUE\nEND\n"
    )
    assert codes(check(src)) == [(8, "output-in-advance-run"), (10, "approximation-lost")]


def test_the_hand_written_program_passes_check():
    texts = [read_source(p, KRL.encodings) for p in sorted(PICKCELL.iterdir())]
    [group] = KRL.programs(texts)
    assert KRL.check_files(group) == []
