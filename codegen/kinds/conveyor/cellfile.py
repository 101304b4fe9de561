"""The conveyor kind's part of the cell file: the [conveyor] table, its pick's inputs and timing budget checked."""

from __future__ import annotations

from codegen import protocol
from codegen.kinds.conveyor import budget
from codegen.kinds.conveyor.keys import KEYS
from codegen.kinds.conveyor.pick import check_inputs
from codegen.kinds.conveyor.section import conveyor_of, parse_conveyor
from codegen.model.robot import check_carried


class SectionPart(protocol.Section):
    keys = KEYS

    def parse(self, ctx, data: dict, cell):
        return parse_conveyor(ctx, data, cell.targets, cell.pose_format)

    def standalone(self, data: dict) -> bool:
        return isinstance(data.get("conveyor"), dict) and "pick" in data["conveyor"]

    def check(self, ctx, cell) -> None:
        conveyor = conveyor_of(cell)
        if conveyor is not None and conveyor.pick is not None and (cell.io is None or not cell.io.feedback):
            ctx.fail("cell.io", "a cell with [conveyor.pick] needs [cell.io] with feedback: the gripper and its sensor")
        if conveyor is not None and conveyor.pick is not None:
            check_inputs(ctx, conveyor.pick, cell.io.feedback, cell.io.output)
            check_carried(ctx, cell.robot, conveyor.pick.part_mass_kg, "conveyor.pick.part_mass_kg")
        budget.check(ctx, cell)
