"""Source 003's automatic tool calibration as a program kind: the [laser] station and its TCP program."""

from __future__ import annotations

from codegen.emit import Emitter
from codegen.kinds.laser import reach
from codegen.kinds.laser.program import calibrates_on, laser_context, laser_file_names
from codegen.kinds.laser.section import laser_of, parse_laser
from codegen.protocol import ProgramFile, ProgramKind, ProgramPlan


class LaserKind(ProgramKind):
    name = "laser"
    order = 40
    tables = frozenset({"laser"})
    target_keys = {
        "files": list,  # source 003's automatic TCP program: file patterns with {laser}
        "names": dict,  # that program's globals verify reads (edges, hits, centres, axis, tcp)
    }

    @classmethod
    def parse_section(cls, ctx, data: dict, cell):
        return parse_laser(ctx, data, cell.targets, cell.pose_format)

    @classmethod
    def standalone(cls, data: dict) -> bool:
        return "laser" in data

    @classmethod
    def check_cell(cls, ctx, cell) -> None:
        robot = cell.robot
        if laser_of(cell) is not None and (robot is None or not robot.tool_given):
            ctx.fail(
                "laser", "a cell with [laser] needs [cell.robot] and [cell.tool]: the arm and the tool to calibrate"
            )

    @classmethod
    def programs(cls, cell, target) -> list[ProgramPlan]:
        """Source 003's automatic TCP program of a cell with [laser]: "tcp_<cell>.mod" from "kinds/laser.mod.j2"."""
        if not calibrates_on(cell, target):
            return []
        context = laser_context(cell, target, Emitter(target))
        files = tuple(
            ProgramFile(name, f"{target.name}/kinds/{pattern.format(laser='laser')}.j2")
            for pattern, name in zip(cls.facts(target)["files"], laser_file_names(cell, target), strict=True)
        )
        return [ProgramPlan(cls.name, context["ident"], files, {"laser": context})]

    @classmethod
    def reach(cls, cell, targets: list[str]) -> list:
        return reach.check(cell, targets)

    @classmethod
    def identities(cls, check) -> list:
        from codegen.kinds.laser import derivation  # sympy: only `codegen derive` pays for it

        return derivation.laser_identities(check)

    @classmethod
    def verify_section(cls, cell, files: tuple, targets: tuple, seed: int):
        from codegen.kinds.laser.verify import laser_section

        return laser_section(cell, files, targets, seed)

    @classmethod
    def commands(cls) -> list:
        from codegen.kinds.laser.commands import calibrate_tcp

        return [("calibrate", calibrate_tcp)]
