"""URScript target."""

from station_base import ArmTests, MotionTests, StationTests, replace_once

WORK = "movel(pose_trans(corr, p1_chuck), a=1.2, v=0.0500)"  # the work pose of station 1 (slow: [cell.motion])


class TestUR(StationTests, MotionTests, ArmTests):
    target = "ur"
    motion_mutations = ["speed_x10", "acceleration_x10", "blend_on_work_pose"]
    arm_mutations = ["qnear_wrist_flipped", "no_tcp", "no_payload", "out_of_reach"]
    arm_words = {
        "qnear_wrist_flipped": ("joints",),
        "no_tcp": ("position error", "joints"),
        "no_payload": ("payload in force is not set",),
        "out_of_reach": ("no solution", "out of reach"),
    }

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
            "qnear_wrist_flipped": lambda: replace_once(  # axes 4 and 6 half a turn on, axis 5 negated
                text, "-1.667386, -1.570796, 2.695794]), a", "1.474207, 1.570796, 5.837387]), a"
            ),
            "no_tcp": lambda: replace_once(text, "  set_tcp(p[0.0000000,", "  textmsg(p[0.0000000,"),
            "no_payload": lambda: replace_once(
                text, "\n  set_target_payload(1.500,", "\n  # set_target_payload(1.500,"
            ),
            "out_of_reach": lambda: replace_once(text, "p1_chuck = p[0.7385000", "p1_chuck = p[2.7385000"),
            "speed_x10": lambda: replace_once(text, WORK, WORK.replace("v=0.0500", "v=0.5")),
            "acceleration_x10": lambda: replace_once(text, WORK, WORK.replace("a=1.2", "a=12")),
            "blend_on_work_pose": lambda: replace_once(text, WORK, WORK.replace("v=0.0500", "v=0.0500, r=0.05")),
        }[mutation]()
