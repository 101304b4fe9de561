"""Source 003's automatic tool calibration as a program kind: the [laser] station and its TCP program."""

from __future__ import annotations

from codegen.controllers import get_target
from codegen.kinds.laser import confirm, plan, reach
from codegen.kinds.laser.commands import calibrate_tcp
from codegen.kinds.laser.keys import KEYS
from codegen.kinds.laser.program import calibrates_on, laser_context, laser_file_names
from codegen.kinds.laser.scene import objects as scene_objects
from codegen.kinds.laser.section import check_production_tools, laser_of, parse_laser
from codegen.kinds.laser.verify import cases, check_goal
from codegen.protocol import ProgramFile, ProgramKind, ProgramPlan
from codegen.render import program_emitter


class LaserKind(ProgramKind):
    name = "laser"
    order = 40
    cell_file = KEYS
    target_keys = {
        "files": list,  # source 003's automatic TCP program: file patterns with {laser}
        "names": dict,  # that program's globals verify reads (edges, hits, centres, axis, tcp)
        "production_tool": dict,  # the production tool the TCP found goes into: form, name, fields, unit
        "joint_zone": bool,  # the program blends into and out of its joint moves (the safe pose)
        "circle_blend_mm": float,  # the first half circle blends into the second by this much (0: it stops)
        "entry_routine": bool,  # the program is a routine of the production task, not a program with its own main
        "confirm": bool,  # the operator confirms the production tool's change (old and new X, Y, Z shown, Yes/No)
    }

    @classmethod
    def parse_section(cls, ctx, data: dict, cell):
        return parse_laser(ctx, data, cell.targets, cell.pose_format)

    @classmethod
    def standalone(cls, data: dict) -> bool:
        return "laser" in data

    @classmethod
    def check_cell(cls, ctx, cell) -> None:
        robot, laser = cell.robot, laser_of(cell)
        if laser is None:
            return
        if robot is None or not robot.tool_given:
            ctx.fail(
                "laser", "a cell with [laser] needs [cell.robot] and [cell.tool]: the arm and the tool to calibrate"
            )
        check_production_tools(ctx, laser, robot, cell.targets)
        # the approach blends above the circles' start (between the way down from the safe pose and the last
        # clearance_mm + d1 to the start) and at the safe pose: a blend reaches at most half a segment
        shortest = min(laser.clearance_mm + laser.depths_mm[0], laser.safe_height_mm - laser.clearance_mm)
        if cell.motion.zone_mm > shortest / 2:
            ctx.fail(
                "cell.motion.zone_mm",
                f"at most {shortest / 2:g} mm with [laser]: half the shortest segment the calibration blends "
                "(from the safe pose down above the start, and from there down to it)",
            )
        check_goal(ctx, cell)

    @classmethod
    def programs(cls, cell, target) -> list[ProgramPlan]:
        """Source 003's automatic TCP program of a cell with [laser]: "tcp_<cell>.mod" from "kinds/laser.mod.j2"."""
        if not calibrates_on(cell, target):
            return []
        emitter = program_emitter(cell, target)
        context = {**laser_context(cell, target, emitter), **confirm.context(cell, target, emitter)}
        files = tuple(
            ProgramFile(name, f"{target.name}/kinds/{pattern.format(laser='laser', data='laser_data')}.j2")
            for pattern, name in zip(cls.facts(target)["files"], laser_file_names(cell, target), strict=True)
        )
        return [ProgramPlan(cls.name, context["ident"], files, {"laser": context}, entry=context["entry"])]

    @classmethod
    def reach(cls, cell, targets: list[str]) -> list:
        return reach.check(cell, targets)

    @classmethod
    def identities(cls, check) -> list:
        from codegen.kinds.laser import derivation  # sympy: only `codegen derive` pays for it

        return derivation.laser_identities(check)

    # --- verify -------------------------------------------------------------------------------
    report_key = "lasers"
    scenarios = {
        "start_away": "",  # away from home and from the station: stopped before the arm moves
        "start_mid_cycle": "",  # where a stopped calibration left it (the first circle's start): out, home, again
        "gripper_silent": "the calibration program uses no gripper",
        "gripper_stuck": "the calibration program uses no gripper",
        "device_late": "the sensors switch with the pin's position, seen once per input cycle of the controller",
        "device_silent": "",  # sensors that never switch
        "reading_out_of_range": "",  # a TCP or an axis beyond offset_max_mm of the tool as designed
    }

    @classmethod
    def verify_cases(cls, cell, source, count: int, seed: int) -> list:
        out = cases(cell, seed)
        return out + confirm.cases(get_target(source.target), out[0]) + plan.production_cases(cell, source.target)

    @classmethod
    def setup(cls, cell, source, case):
        return plan.setup(cell, source.target, case)

    @classmethod
    def judge(cls, cell, source, case, trace, setup):
        return plan.judge(cell, source.target, case, trace)

    @classmethod
    def new_figures(cls):
        return plan.LaserFigures()

    @classmethod
    def add_figures(cls, figures, case, judged) -> None:
        plan.add(figures, judged)

    @classmethod
    def merge_figures(cls, into, part) -> None:
        plan.merge(into, part)

    @classmethod
    def summary(cls, row) -> dict:
        f = row.figures or plan.LaserFigures()
        return {
            "tcp_truth_max_mm": f.truth_max_mm,
            "tcp_with_frame_error_mm": f.frame_error_mm,
            "motion_s": f.motion_s,
        }

    @classmethod
    def legacy_summary(cls, row) -> dict:
        return plan.legacy_summary(row)

    @classmethod
    def report_lines(cls, rows: list) -> list[str]:
        return plan.report_lines(rows)

    @classmethod
    def scene(cls, cell) -> list[dict]:
        return [] if cls.section(cell) is None else scene_objects(cell, cls.section(cell))

    @classmethod
    def commands(cls) -> list:
        return [("calibrate", calibrate_tcp)]
