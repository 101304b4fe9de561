"""The pallet kind's programs: a stacking program per [[pallet]] and target (or one task of them all), and their
reach proof."""

from __future__ import annotations

from codegen import protocol
from codegen.emit import EmitError
from codegen.kinds.pallet import plan
from codegen.kinds.pallet.kind import KIND
from codegen.kinds.pallet.program import check_level, file_name, identifiers, pallet_context, task_context
from codegen.kinds.pallet.section import pallets_of
from codegen.protocol import ProgramFile, ProgramPlan
from codegen.render import program_emitter

FORMS_PER_PALLET = 2  # a plan's index is 2 x its pallet's + its form (the program, its Script-node twin)


class WriterPart(protocol.Writer):
    def programs(self, cell, target) -> list[ProgramPlan]:
        """Each [[pallet]]'s program: "pal_<name>.src" from the template "kinds/pallet.src.j2" (a data list, a
        Script-node twin); where the target runs them in one task, one program of every pallet's module."""
        pallets = pallets_of(cell)
        if not pallets:
            return []
        facts = KIND.facts(target)
        if facts.get("task") and cell.stations_section() is not None:
            raise EmitError(
                f"{target.name}: the cell's station program and its pallet programs would each have a PROC main in "
                "one task: give the pallets a cell file of their own"
            )
        emitter = program_emitter(cell, target)
        contexts, owns = [], identifiers(cell, target)
        for index, pallet in enumerate(pallets):
            check_level(pallet, target)
            contexts.append(pallet_context(cell, pallet, index, target, emitter))

        def files(patterns: list[str], index: int) -> list[ProgramFile]:
            return [
                ProgramFile(file_name(target, p, owns[index]), f"{target.name}/kinds/{p.format(pallet='pallet')}.j2")
                for p in patterns
            ]

        if facts.get("task"):  # one program: the task's modules once, each pallet's module with its variables
            out = []
            for pattern in facts["files"]:
                if "{pallet}" not in pattern:
                    out += files([pattern], 0)
                    continue
                for index, context in enumerate(contexts):
                    (own,) = files([pattern], index)
                    out.append(ProgramFile(own.name, own.template, {"pallet": context}))
            ident = out[0].name.split(".")[0]
            return [ProgramPlan(KIND.name, ident, tuple(out), task_context(cell, target, emitter, contexts), 0)]
        plans = []
        forms = [facts["files"], *([facts["node_files"]] if "node_files" in facts else [])]
        for index, context in enumerate(contexts):
            for form, patterns in enumerate(forms):
                own = files(patterns, index)
                ident = own[0].name.split(".")[0]
                number = FORMS_PER_PALLET * index + form
                plans.append(ProgramPlan(KIND.name, ident, tuple(own), {"pallet": context}, number))
        return plans

    def reach(self, cell, targets: list[str]) -> list:
        return plan.check(cell, targets)
