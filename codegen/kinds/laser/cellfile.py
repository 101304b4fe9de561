"""The laser kind's part of the cell file: the [laser] table, with the arm, the tool and the blends it needs."""

from __future__ import annotations

from codegen import protocol
from codegen.kinds.laser.budget import check_goal
from codegen.kinds.laser.keys import KEYS
from codegen.kinds.laser.section import check_production_tools, laser_of, parse_laser


class SectionPart(protocol.Section):
    keys = KEYS

    def parse(self, ctx, data: dict, cell):
        return parse_laser(ctx, data, cell.targets, cell.pose_format)

    def standalone(self, data: dict) -> bool:
        return "laser" in data

    def check(self, ctx, cell) -> None:
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
