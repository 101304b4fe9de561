"""KUKA KRL target."""

from station_base import ArmTests, HaltGoesOnTests, MotionTests, StationTests, replace_once

from codegen.kinds.station.section import stations_of

WORK = "  TARGET = CORR : P1_CHUCK\n  $VEL.CP = 0.0500\n  LIN TARGET\n"  # the work pose of station 1 (slow)
BASE_RESET = "  $BASE = $ROBROOT ; the robot's base ($NULLFRAME is the world: not the same on a track or a platform)\n"
HALT_RETURN = "    VIS_PAR[1] = {PAR_TYPE #EMPTY}\n    VIS_HALT()\n    RETURN\n"  # a station's guard halt
LIN_TARGET = "{X 600,Y 0,Z 700,A 0,B 90,C 0}"  # a first motion that is no PTP to a full position
INITMOV = "  BAS(#INITMOV, 0)\n"


P3_APPROACH = "P3_APPROACH={X 600.0000,Y 40.0000,Z 450.0000,A -90.000000,B 15.000000,C 180.000000"


class TestKUKA(StationTests, MotionTests, ArmTests, HaltGoesOnTests):
    target = "kuka"
    motion_mutations = ["no_base_reset", "approximated_work_pose", "ptp_at_full_speed"]
    arm_stations = (1, 3)  # station 3's approach names S and T (station 1's, A4 at 0, names S alone)
    arm_mutations = ["status_changed", "turn_changed", "no_tool", "no_load", "out_of_reach", "lin_first"]
    arm_words = {
        "status_changed": ("cannot reach this pose in configuration [6, 10]",),
        "turn_changed": ("cannot reach this pose in configuration [2, 11]",),
        "no_tool": ("position error", "joints"),
        "no_load": ("payload in force is not set",),
        "out_of_reach": ("out of reach", "cannot reach"),
        "lin_first": ("BCO",),
    }

    def mutate(self, mutation, text, dat):
        return {
            "swap_sin_cos": lambda: replace_once(text, "COS_PHI = COS(PHI)", "COS_PHI = SIN(PHI)"),
            "flip_sign": lambda: replace_once(text, "PHI = ANGLE_SIGN *", "PHI = -ANGLE_SIGN *"),
            "drop_guard": lambda: replace_once(text, "IF DX * DX + DY * DY > MAX_SHIFT_SQ THEN", "IF FALSE THEN"),
            "calibration_number": lambda: (text, replace_once(dat, "X 612.400000", "X 612.450000")),
            "extra_dispatch_id": lambda: (replace_once(text, "  CASE 1\n", "  CASE 1, 20000\n"), dat),
            "halt_goes_on": lambda: (replace_once(text, HALT_RETURN, HALT_RETURN.replace("    RETURN\n", "")), dat),
            # station 3's approach (a PTP): its tool tilted 15 deg, every axis clear of 0, so it names S and T
            "status_changed": lambda: (text, replace_once(dat, P3_APPROACH + ",S 2,T 10", P3_APPROACH + ",S 6,T 10")),
            "turn_changed": lambda: (text, replace_once(dat, P3_APPROACH + ",S 2,T 10", P3_APPROACH + ",S 2,T 11")),
            "no_tool": lambda: (replace_once(text, "  $TOOL = VIS_TOOL\n", ""), dat),
            "no_load": lambda: (replace_once(text, "  $LOAD = VIS_LOAD\n", ""), dat),
            "out_of_reach": lambda: (text, replace_once(dat, "P1_CHUCK={X 738.5000", "P1_CHUCK={X 2738.5000")),
            "lin_first": lambda: (replace_once(text, "  PTP VIS_HOME\n", f"  LIN {LIN_TARGET}\n"), dat),
            # BAS(#INITMOV) sets $BASE = $WORLD (KUKA's BAS.SRC): a program that never sets its base has neither
            "no_base_reset": lambda: (replace_once(replace_once(text, BASE_RESET, ""), INITMOV, ""), dat),
            "ptp_at_full_speed": lambda: (replace_once(text, "BAS(#VEL_PTP, 30.0)", "BAS(#VEL_PTP, 100)"), dat),
            "approximated_work_pose": lambda: (
                replace_once(text, WORK, WORK.replace("TARGET\n", "TARGET C_DIS\n")),
                dat,
            ),
        }[mutation]()


def test_the_base_is_the_robot_base_on_a_platform():
    """With $ROBROOT not null (an arm on a platform or a track) the program's $BASE = $ROBROOT keeps every
    move in the robot's base frame; $BASE = $NULLFRAME (the world) would move the arm by $ROBROOT."""
    import numpy as np

    from codegen.controllers import get_target
    from codegen.dialects.core.files import SourceFile
    from codegen.dialects.krl.modules import load_files
    from codegen.kinds.station.cases import inputs_for, run_options
    from codegen.kinds.station.mode import get_mode
    from codegen.model.cell import load_cell
    from codegen.render import render

    cell, target = load_cell(), get_target("kuka")
    rendered = render(cell, ["kuka"])
    files = {f.relpath.rsplit(".", 1)[1]: f.text for f in rendered}
    # the vision channel's configuration, named as EKI_Init opens it
    xml = next(SourceFile(f.relpath.rsplit("/", 1)[-1], f.text) for f in rendered if f.relpath.endswith(".xml"))
    case = get_mode("point").nominal_case(cell, stations_of(cell)[0])
    inputs = inputs_for(cell, target, case.reading)
    root = {"$ROBROOT": (1500.0, -300.0, 0.0, 90.0, 0.0, 0.0)}

    def moves(src: str, extra: dict) -> list:
        program = load_files([SourceFile("p.src", src), SourceFile("p.dat", files["dat"]), xml])
        trace = program.run({**inputs, **extra}, **run_options(cell, target, case))
        assert not trace.halted, trace.halt_message
        return [m.tcp2base for m in trace.moves if m.tcp2base is not None]

    on_floor, on_platform = moves(files["src"], {}), moves(files["src"], root)
    assert len(on_floor) == len(on_platform) >= 2
    assert all(np.allclose(a, b, atol=1e-3) for a, b in zip(on_floor, on_platform, strict=True))
    world = moves(replace_once(files["src"], BASE_RESET, "  $BASE = $NULLFRAME\n"), root)
    assert all(np.linalg.norm(a[:3, 3] - b[:3, 3]) > 1000 for a, b in zip(on_floor, world, strict=True))
