"""KUKA KRL target."""

from target_base import TargetTests, replace_once

WORK = "  TARGET = CORR : P1_CHUCK\n  LIN TARGET\n"  # the work pose of station 1
LIN_TARGET = "{X 600,Y 0,Z 700,A 0,B 90,C 0}"  # a first motion that is no PTP to a full position


class TestKUKA(TargetTests):
    target = "kuka"
    motion_mutations = ["no_base_reset", "approximated_work_pose"]
    arm_mutations = ["status_changed", "turn_changed", "no_tool", "no_load", "out_of_reach", "lin_first"]
    arm_words = {
        "status_changed": ("cannot reach this pose in configuration [6, 34]",),
        "turn_changed": ("cannot reach this pose in configuration [2, 35]",),
        "no_tool": ("position error", "joints"),
        "no_load": ("load None",),
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
            "halt_goes_on": lambda: (replace_once(text, "    VIS_HALT()\n    RETURN\n", "    VIS_HALT()\n"), dat),
            "status_changed": lambda: (text, replace_once(dat, "C 180.000000,S 2,T 34", "C 180.000000,S 6,T 34")),
            "turn_changed": lambda: (text, replace_once(dat, "C 180.000000,S 2,T 34", "C 180.000000,S 2,T 35")),
            "no_tool": lambda: (replace_once(text, "  $TOOL = VIS_TOOL\n", ""), dat),
            "no_load": lambda: (replace_once(text, "  $LOAD = VIS_LOAD\n", ""), dat),
            "out_of_reach": lambda: (text, replace_once(dat, "P1_CHUCK={X 738.5000", "P1_CHUCK={X 2738.5000")),
            "lin_first": lambda: (replace_once(text, "  PTP VIS_HOME\n", f"  LIN {LIN_TARGET}\n"), dat),
            "no_base_reset": lambda: (replace_once(text, "  $BASE = $NULLFRAME\n  $TOOL", "  $TOOL"), dat),
            "approximated_work_pose": lambda: (
                replace_once(text, WORK, WORK.replace("TARGET\n", "TARGET C_DIS\n")),
                dat,
            ),
        }[mutation]()
