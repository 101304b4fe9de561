"""The conveyor kind's program: the pick-from-belt program of a cell with [conveyor.pick], and its reach proof."""

from __future__ import annotations

from codegen import protocol
from codegen.kinds.conveyor import reach
from codegen.kinds.conveyor.kind import KIND
from codegen.kinds.conveyor.program import conveyor_context, conveyor_file_names, picks_on
from codegen.protocol import ProgramFile, ProgramPlan
from codegen.render import program_emitter


class WriterPart(protocol.Writer):
    def programs(self, cell, target) -> list[ProgramPlan]:
        """ "cnv_<cell>.script" from the template "kinds/conveyor.script.j2" (each target's files)."""
        if not picks_on(cell, target):
            return []
        context = conveyor_context(cell, target, program_emitter(cell, target))
        files = tuple(
            ProgramFile(name, f"{target.name}/kinds/{pattern.format(conveyor='conveyor', data='conveyor_data')}.j2")
            for pattern, name in zip(KIND.facts(target)["files"], conveyor_file_names(cell, target), strict=True)
        )
        return [ProgramPlan(KIND.name, context["ident"], files, {"conveyor": context})]

    def reach(self, cell, targets: list[str]) -> list:
        return reach.check(cell, targets)
