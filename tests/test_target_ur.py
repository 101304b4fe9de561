"""URScript target."""

from target_base import TargetTests, replace_once


class TestUR(TargetTests):
    target = "ur"

    def mutate(self, mutation, text, dat):
        return {
            "swap_sin_cos": lambda: replace_once(text, "cos_phi = cos(phi)", "cos_phi = sin(phi)"),
            "flip_sign": lambda: replace_once(text, "phi = d2r(ANGLE_SIGN *", "phi = d2r(-ANGLE_SIGN *"),
            "drop_guard": lambda: replace_once(text, "if dx * dx + dy * dy > MAX_SHIFT_SQ:", "if False:"),
            "calibration_number": lambda: replace_once(text, "612.400000", "612.450000"),
            "extra_dispatch_id": lambda: replace_once(
                text,
                "  elif station_id == 2:",
                "  elif station_id == 20000:\n    st_lathe_1()\n  elif station_id == 2:",
            ),
        }[mutation]()
