"""The laser kind's program: source 003's automatic TCP program of a cell with [laser], and its reach proof."""

from __future__ import annotations

from codegen import protocol
from codegen.kinds.laser import confirm, frame_setup, reach
from codegen.kinds.laser.kind import KIND
from codegen.kinds.laser.program import calibrates_on, laser_context, laser_file_names
from codegen.protocol import ProgramFile, ProgramPlan
from codegen.render import program_emitter


class WriterPart(protocol.Writer):
    def programs(self, cell, target) -> list[ProgramPlan]:
        """ "tcp_<cell>.mod" from "kinds/laser.mod.j2" (each target's files)."""
        if not calibrates_on(cell, target):
            return []
        emitter = program_emitter(cell, target)
        context = {**laser_context(cell, target, emitter), **confirm.context(cell, target, emitter)}
        files = tuple(
            ProgramFile(name, f"{target.name}/kinds/{pattern.format(laser='laser', data='laser_data')}.j2")
            for pattern, name in zip(KIND.facts(target)["files"], laser_file_names(cell, target), strict=True)
        )
        plans = [ProgramPlan(KIND.name, context["ident"], files, {"laser": context}, entry=context["entry"])]
        if frame_setup.sets_up(cell, target):
            frame = frame_setup.frame_context(cell, target, emitter)
            frame_files = tuple(
                ProgramFile(
                    pattern.format(frame=frame["ident"].lower()),
                    f"{target.name}/kinds/{pattern.format(frame='laser_frame')}.j2",
                )
                for pattern in KIND.facts(target)["frame_files"]
            )
            plans.append(
                ProgramPlan(
                    KIND.name,
                    frame["ident"],
                    frame_files,
                    {"laser": context, "frame": frame},
                    index=1,
                    entry=frame["entry"],
                )
            )
        return plans

    def reach(self, cell, targets: list[str]) -> list:
        return reach.check(cell, targets)
