"""KUKA KRL target."""

from target_base import TargetTests, replace_once

WORK = "  TARGET = CORR : P1_CHUCK\n  LIN TARGET\n"  # the work pose of station 1


class TestKUKA(TargetTests):
    target = "kuka"
    motion_mutations = ["no_base_reset", "approximated_work_pose"]

    def mutate(self, mutation, text, dat):
        return {
            "swap_sin_cos": lambda: replace_once(text, "COS_PHI = COS(PHI)", "COS_PHI = SIN(PHI)"),
            "flip_sign": lambda: replace_once(text, "PHI = ANGLE_SIGN *", "PHI = -ANGLE_SIGN *"),
            "drop_guard": lambda: replace_once(text, "IF DX * DX + DY * DY > MAX_SHIFT_SQ THEN", "IF FALSE THEN"),
            "calibration_number": lambda: (text, replace_once(dat, "X 612.400000", "X 612.450000")),
            "extra_dispatch_id": lambda: (replace_once(text, "  CASE 1\n", "  CASE 1, 20000\n"), dat),
            "halt_goes_on": lambda: (replace_once(text, "    VIS_HALT()\n    RETURN\n", "    VIS_HALT()\n"), dat),
            "no_base_reset": lambda: (replace_once(text, "  $BASE = $NULLFRAME\n  SWITCH", "  SWITCH"), dat),
            "approximated_work_pose": lambda: (
                replace_once(text, WORK, WORK.replace("TARGET\n", "TARGET C_DIS\n")),
                dat,
            ),
        }[mutation]()
