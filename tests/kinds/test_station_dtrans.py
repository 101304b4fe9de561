"""Decompose/Trans target."""

from station_base import StationTests, replace_once


class TestDTrans(StationTests):
    target = "dtrans"

    def mutate(self, mutation, text, dat):
        return {
            "swap_sin_cos": lambda: replace_once(text, "Double cos_phi = cos(phi)", "Double cos_phi = sin(phi)"),
            "flip_sign": lambda: replace_once(text, "Double phi = ANGLE_SIGN *", "Double phi = -ANGLE_SIGN *"),
            "drop_guard": lambda: replace_once(text, "If dx * dx + dy * dy > MAX_SHIFT_SQ Then", "If False Then"),
            "calibration_number": lambda: replace_once(text, "612.400000", "612.450000"),
            "extra_dispatch_id": lambda: replace_once(
                text,
                "ElseIf weizhi == 2 Then",
                "ElseIf weizhi == 20000 Then\n  Call st_lathe_1()\nElseIf weizhi == 2 Then",
            ),
        }[mutation]()
