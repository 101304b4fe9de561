"""KUKA KRL target."""

from target_base import TargetTests, replace_once


class TestKUKA(TargetTests):
    target = "kuka"

    def mutate(self, mutation, text, dat):
        return {
            "swap_sin_cos": lambda: replace_once(text, "COS_PHI = COS(PHI)", "COS_PHI = SIN(PHI)"),
            "flip_sign": lambda: replace_once(text, "PHI = ANGLE_SIGN *", "PHI = -ANGLE_SIGN *"),
            "drop_guard": lambda: replace_once(text, "IF DX * DX + DY * DY > MAX_SHIFT_SQ THEN", "IF FALSE THEN"),
            "calibration_number": lambda: (text, replace_once(dat, "X 612.400000", "X 612.450000")),
            "extra_dispatch_id": lambda: (replace_once(text, "  CASE 1\n", "  CASE 1, 20000\n"), dat),
            "halt_goes_on": lambda: (replace_once(text, "    VIS_HALT()\n    RETURN\n", "    VIS_HALT()\n"), dat),
        }[mutation]()
