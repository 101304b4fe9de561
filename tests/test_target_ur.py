"""URScript target."""

from target_base import TargetTests, replace_once

WORK = "movel(pose_trans(corr, p1_chuck), a=1.2, v=0.25)"  # the work pose of station 1


class TestUR(TargetTests):
    target = "ur"
    motion_mutations = ["speed_x10", "acceleration_x10", "blend_on_work_pose"]

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
            "speed_x10": lambda: replace_once(text, WORK, WORK.replace("v=0.25", "v=2.5")),
            "acceleration_x10": lambda: replace_once(text, WORK, WORK.replace("a=1.2", "a=12")),
            "blend_on_work_pose": lambda: replace_once(text, WORK, WORK.replace("v=0.25", "v=0.25, r=0.05")),
        }[mutation]()
