"""The toy kind's program: toy_<cell>.script on the targets it has a template for (UR)."""

from __future__ import annotations

from codegen import protocol
from codegen.protocol import ProgramFile, ProgramPlan
from codegen.render import file_stem, program_emitter

TEMPLATES = {"ur": "ur/toy.script.j2"}  # the targets it writes for: its template in its own folder


class ToyWriter(protocol.Writer):
    def programs(self, cell, target) -> list[ProgramPlan]:
        toy = self.kind.section.of(cell)
        if toy is None or target.name not in TEMPLATES:
            return []
        emitter = program_emitter(cell, target)
        ident = emitter.identifier("toy_", cell.name, "cell name")
        context = {"toy": {"ident": ident, "greeting": emitter.string(toy.greeting)}}
        name = f"toy_{file_stem(cell, target)}.script"
        return [ProgramPlan(self.kind.name, str(ident), (ProgramFile(name, TEMPLATES[target.name]),), context)]
