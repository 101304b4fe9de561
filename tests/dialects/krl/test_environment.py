"""The controller's environment: the built-in $config.dat and one given, BAS, the inline forms, system variables."""

from __future__ import annotations

import numpy as np
import pytest

from codegen.dialects.core.values import RunError
from codegen.robot.arms import find_arm

from .helpers import INI, KRL, files, program, run

POSE = "{X 500,Y 0,Z 600,A 0,B 90,C 0,S 2,T 35}"
TOOL = "TOOL_DATA[1]={X 0,Y 0,Z 120,A 0,B 0,C 0}\nBASE_DATA[2]={X 100,Y 200,Z 0,A 90,B 0,C 0}"
FOLD_PTP = (
    ";FOLD PTP P1 Vel=50 % PDAT1 Tool[1] Base[2];%{{PE}}%R 8.3.38,%MKUKATPBASIS,%CMOVE,%VPTP,%P 1:PTP, 2:P1\n"
    "$BWDSTART=FALSE\nPDAT_ACT=PPDAT1\nFDAT_ACT=FP1\nBAS(#PTP_PARAMS,{vel})\nPTP XP1\n;ENDFOLD\n"
)
FOLD_LIN = (
    ";FOLD LIN P2 CONT Vel=0.4 m/s CPDAT1 Tool[1] Base[2];%{{PE}}%MKUKATPBASIS,%CMOVE,%VLIN,%P 1:LIN, 2:P2\n"
    "$BWDSTART=FALSE\nLDAT_ACT=LCPDAT1\nFDAT_ACT=FP1\nBAS(#CP_PARAMS,{vel})\nLIN XP2 C_DIS\n;ENDFOLD\n"
)
INLINE_DAT = (
    "DECL E6POS XP1={X 400,Y 0,Z 500,A 0,B 90,C 0,S 2,T 35,E1 0,E2 0,E3 0,E4 0,E5 0,E6 0}\n"
    'DECL FDAT FP1={TOOL_NO 1,BASE_NO 2,IPO_FRAME #BASE,POINT2[] " ",TQ_STATE FALSE}\n'
    "DECL PDAT PPDAT1={VEL 50.0,ACC 80.0,APO_DIST 100.0,APO_MODE #CDIS,GEAR_JERK 50.0,EXAX_IGN 0}\n"
    "DECL E6POS XP2={X 400,Y 50,Z 500,A 0,B 90,C 0,S 2,T 35,E1 0,E2 0,E3 0,E4 0,E5 0,E6 0}\n"
    "DECL LDAT LCPDAT1={VEL 2.0,ACC 50.0,APO_DIST 25.0,APO_FAC 50.0,AXIS_VEL 100.0,AXIS_ACC 100.0,ORI_TYP #VAR,"
    "CIRC_TYP #BASE,JERK_FAC 50.0,GEAR_JERK 50.0,EXAX_IGN 0}\n"
)


def test_initmov_sets_what_bas_src_sets():
    """BAS(#INITMOV, 0): DEF_VEL_CP 2 m/s, PTP at 100 % of DEF_VEL_PTP, DEF_ACC_PTP 50 %, $APO.CDIS 3 mm,
    $BASE = $WORLD (the robot's base here), $ADVANCE 3."""
    trace = program(INI + f"PTP {POSE}\nLIN {{X 500,Y 10,Z 600,A 0,B 90,C 0}} C_DIS").run({}, keep=())
    ptp, lin = trace.moves
    assert (ptp.settings["vel_ptp"], ptp.settings["acc_ptp"]) == (100.0, 50.0)
    assert (lin.settings["vel_cp"], lin.settings["cdis"], lin.settings["acc_cp"]) == (2.0, 3.0, pytest.approx(2.3))
    assert ptp.tcp2base[:3, 3].tolist() == pytest.approx([500.0, 0.0, 600.0])  # in $WORLD, no base moved it


def test_without_initmov_a_program_moves_in_the_base_it_found():
    trace = run(f"PTP {POSE}")
    assert trace.moves[0].tcp2base[:3, 3].tolist() != pytest.approx([500.0, 0.0, 600.0])


def test_the_inline_forms_set_speed_tool_and_base_from_their_data():
    body = INI + FOLD_PTP.format(vel=50) + FOLD_LIN.format(vel=0.4) + "TOOL_Z = $TOOL.Z"
    prog = program(body, dat=INLINE_DAT + "DECL REAL TOOL_Z")
    tool = {"TOOL_DATA[1]": (0.0, 0.0, 120.0, 0.0, 0.0, 0.0), "BASE_DATA[2]": (100.0, 200.0, 0.0, 90.0, 0.0, 0.0)}
    trace = prog.run(tool, keep=("TOOL_Z",))
    ptp, lin = trace.moves
    assert (ptp.settings["vel_ptp"], ptp.settings["acc_ptp"]) == (50.0, 40.0)  # 80 % of DEF_ACC_PTP 50
    assert (lin.settings["vel_cp"], lin.settings["cdis"], lin.settings["acc_cp"]) == (
        pytest.approx(0.4),
        25.0,
        pytest.approx(2.3 * 0.5),
    )
    assert ptp.tcp2base[:3, 3].tolist() == pytest.approx([100.0, 600.0, 500.0])  # BASE_DATA[2] turned 90 deg
    assert trace.kept == {"TOOL_Z": 120.0}  # FDAT's TOOL_NO 1: TOOL_DATA[1]


def test_a_tool_nothing_gives_is_a_fresh_controllers_zero_frame_with_a_warning_naming_it():
    trace = program(INI + FOLD_PTP.format(vel=50), dat=INLINE_DAT).run({})
    named = [w.split(" is not set")[0] for w in trace.warnings]
    assert named == ["TOOL_DATA[1]", "BASE_DATA[2]"]  # FDAT's TOOL_NO 1 and BASE_NO 2, as BAS reads them
    assert all("taken as a fresh controller has it (a zero frame)" in w for w in trace.warnings)


def test_a_given_config_dat_replaces_the_built_in_names():
    config = (
        "DEFDAT $CONFIG\nE6AXIS XHOME={A1 10,A2 -80,A3 80,A4 0,A5 30,A6 0,E1 0,E2 0,E3 0,E4 0,E5 0,E6 0}\n"
        "SIGNAL GRIPPER_OPEN $OUT[5]\nDECL FRAME TOOL_DATA[16]\n" + TOOL + "\nENDDAT\n"
    )
    main = f"DEF CELL()\n{INI}PTP XHOME\nGRIPPER_OPEN = TRUE\nPTP {POSE}\nEND\n"
    built_in = KRL.load_files(files(cell_src=main.replace("GRIPPER_OPEN = TRUE\n", ""))).run({})
    assert list(built_in.moves[0].joints) == [0.0, -90.0, 90.0, 0.0, 0.0, 0.0]  # KSS's XHOME as shipped
    trace = KRL.load_files(files(cell_src=main, config_dat=config)).run({})
    assert list(trace.moves[0].joints) == [10.0, -80.0, 80.0, 0.0, 30.0, 0.0]
    assert [(o.name, o.value) for o in trace.outputs] == [("$OUT[5]", True)]
    flange_z = trace.moves[1].tcp2base[2, 3]
    assert flange_z == pytest.approx(600.0)  # TOOL_DATA[1] of the $config.dat, set by INITMOV: no other tool


def test_pdefault_fhome_and_ldefault_are_there():
    body = "PDAT_ACT = PDEFAULT\nFDAT_ACT = FHOME\nLDAT_ACT = LDEFAULT\nN = FHOME.TOOL_NO + PDEFAULT.VEL"
    assert program(body, dat="DECL REAL N").run({}, keep=("N",)).kept == {"N": 101.0}


def test_bas_tool_and_base_numbers():
    trace = program("BAS(#TOOL, 1)\nBAS(#BASE, 2)\nBAS(#VEL_PTP, 200)\n" + f"PTP {POSE}").run(
        {"TOOL_DATA[1]": (0, 0, 120, 0, 0, 0), "BASE_DATA[2]": (100, 200, 0, 90, 0, 0)}
    )
    assert trace.moves[0].tcp2base[:3, 3].tolist() == pytest.approx([100.0, 700.0, 600.0])
    assert trace.moves[0].settings["vel_ptp"] == 100.0  # over 100 %: DEF_VEL_PTP (BAS.SRC)
    with pytest.raises(RunError, match=r"BAS: unknown command #FLY"):
        run("BAS(#FLY, 1)")
    with pytest.raises(RunError, match=r"BAS\(#GROUP\) is not modelled"):
        run("BAS(#GROUP, 1)")


def test_pos_act_and_axis_act_are_where_the_arm_arrived():
    body = INI + f"PTP {POSE}\nLIN {{X 500,Y 50,Z 600,A 0,B 90,C 0}}\nP = $POS_ACT\nQ = $AXIS_ACT"
    trace = program(body, dat="DECL E6POS P\nDECL E6AXIS Q").run({}, arm=find_arm("KR 10 R1100 sixx"), keep=("P", "Q"))
    assert (float(trace.kept["P"]["X"]), float(trace.kept["P"]["Y"])) == pytest.approx((500.0, 50.0), abs=1e-3)
    assert float(trace.kept["Q"]["A1"]) == pytest.approx(trace.moves[1].joints[0], abs=1e-3)
    assert (trace.kept["P"]["S"], trace.kept["P"]["T"]) == (2, 35)  # the configuration it stands in
    back = program(body + "\nPTP P", dat="DECL E6POS P\nDECL E6AXIS Q").run({}, arm=find_arm("KR 10 R1100 sixx"))
    assert np.allclose(back.moves[2].joints, back.moves[1].joints, atol=1e-3)  # PTP $POS_ACT: where it stands
    with pytest.raises(RunError, match=r"\$POS_ACT: the arm's position is not known here"):
        program("P = $POS_ACT", dat="DECL E6POS P").run({})


def test_in_home_compares_the_axes_with_h_pos():
    body = INI + "PTP XHOME\nAT_HOME = $IN_HOME\n" + f"PTP {POSE}\nAWAY = $IN_HOME"
    trace = program(body, dat="DECL BOOL AT_HOME\nDECL BOOL AWAY").run(
        {}, arm=find_arm("KR 10 R1100 sixx"), keep=("AT_HOME", "AWAY")
    )
    assert trace.kept == {"AT_HOME": True, "AWAY": False}


def test_timers_count_with_the_clock_and_wait_for_a_timer_flag():
    body = (
        "$TIMER[1] = -500\n$TIMER_STOP[1] = FALSE\nWAIT FOR $TIMER_FLAG[1]\nT1 = $TIMER[1]\n"
        "WAIT SEC 1.0\n$TIMER_STOP[1] = TRUE\nT2 = $TIMER[1]\nWAIT SEC 1.0\nT3 = $TIMER[1]"
    )
    kept = program(body, dat="DECL INT T1\nDECL INT T2\nDECL INT T3").run({}, keep=("T1", "T2", "T3")).kept
    assert 0 <= kept["T1"] <= 12  # within a controller cycle of 0
    assert kept["T2"] == pytest.approx(kept["T1"] + 1000, abs=1) and kept["T3"] == kept["T2"]


def test_a_wait_for_a_stopped_timer_waits_for_ever():
    with pytest.raises(RunError, match="waits forever"):
        run("$TIMER[2] = -10\nWAIT FOR $TIMER_FLAG[2]")


def test_advance_zero_waits_for_each_motion_and_settings_are_recorded():
    body = INI + f"$OV_PRO = 50\n$ADVANCE = 0\nPTP {POSE}\n$OUT[1] = TRUE\n$BWDSTART = FALSE"
    trace = run(body.replace("$OUT[1] = TRUE", "CONTINUE\n$OUT[1] = TRUE"))
    assert trace.moves[0].settings["ov_pro"] == 50
    assert trace.outputs[0].moving is False  # $ADVANCE 0: the program waited for the motion
    ahead = run(body.replace("$ADVANCE = 0", "$ADVANCE = 3").replace("$OUT[1] = TRUE", "CONTINUE\n$OUT[1] = TRUE"))
    assert ahead.outputs[0].moving is True
    with pytest.raises(RunError, match=r"\$ADVANCE takes 0\.\.5"):
        run("$ADVANCE = 9")


def test_system_variables_not_modelled_are_refused_by_name():
    with pytest.raises(RunError, match=r"t\.src:3:1: the system variable \$SEN_PINT is not modelled"):
        program("$SEN_PINT[1] = 3")
    with pytest.raises(RunError, match=r"\$ANIN is not modelled by this interpreter \(analog inputs"):
        program("R = $ANIN[1]", dat="DECL REAL R")


def test_workspaces_are_recorded_only():
    trace = program("$WORKSPACE[1].MODE = #INSIDE_STOP\nON = $WORKSPACE[1].MODE == #INSIDE_STOP", dat="DECL BOOL ON")
    assert trace.run({}, keep=("ON",)).kept == {"ON": True}


def test_pulse_sets_an_output_for_a_time():
    trace = run("PULSE($OUT[6], TRUE, 0.5)\nWAIT SEC 1")
    assert [(o.name, o.value, o.time) for o in trace.outputs] == [("$OUT[6]", True, 0.0), ("$OUT[6]", False, 0.5)]


def test_pulse_of_a_signal_name_of_one_output():
    # SIGNAL SACO $OUT[3] in $config.dat: the name is that one output (a group of several is refused by name)
    config = "DEFDAT $CONFIG\nSIGNAL SACO $OUT[3]\nSIGNAL PAIR $OUT[4] TO $OUT[5]\nENDDAT\n"
    main = "DEF CELL()\nPULSE(SACO, TRUE, 0.5)\nWAIT SEC 1\nEND\n"
    trace = KRL.load_files(files(cell_src=main, config_dat=config)).run({})
    assert [(o.name, o.value, o.time) for o in trace.outputs] == [("$OUT[3]", True, 0.0), ("$OUT[3]", False, 0.5)]
    with pytest.raises(RunError, match=r"cell\.src:2:1: PULSE: PAIR is 2 signals \$OUT\[4\] TO \$OUT\[5\]"):
        KRL.load_files(files(cell_src=main.replace("SACO", "PAIR"), config_dat=config))


USER_PDAT = "DEFDAT  $CONFIG\nSTRUC PDAT REAL VEL,ACC,APO_DIST\nDECL PDAT PMINE={VEL 40.0,ACC 50.0,APO_DIST 5.0}\n"


def test_a_given_config_dat_s_types_take_the_place_of_the_built_in_ones():
    # a controller's own $config.dat declares STRUC PDAT (its own components): the built-in's PDAT and its data
    # written for it (PDEFAULT's APO_MODE...) give way; what the given one lacks (XHOME, FDAT...) is still there
    main = f"DEF CELL()\n{INI}PTP XHOME\nN = PMINE.VEL + FHOME.TOOL_NO\nEND\n"
    trace = KRL.load_files(files(cell_src=main, config_dat=USER_PDAT + "DECL REAL N\nENDDAT\n")).run({}, keep=("N",))
    assert list(trace.moves[0].joints) == [0.0, -90.0, 90.0, 0.0, 0.0, 0.0]
    assert trace.kept == {"N": 41.0}


def test_a_fault_in_a_given_config_dat_names_its_own_line():
    config = USER_PDAT + "DECL PDAT PBAD={VEL 1.0,APO_MODE #CDIS}\nENDDAT\n"
    with pytest.raises(RunError, match=r"^\$config\.dat:4:\d+: PDAT has no component APO_MODE"):
        KRL.load_files(files(cell_src=f"DEF CELL()\n{INI}PTP XHOME\nEND\n", config_dat=config)).run({})
