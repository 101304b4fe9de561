"""Palletizing (source 004) as a program kind: the [[pallet]] tables, a stacking program per pallet and target."""

from __future__ import annotations

from codegen.emit import EmitError
from codegen.kinds.pallet import reach, verify
from codegen.kinds.pallet.analysis import checked_pallets
from codegen.kinds.pallet.commands import pallet as pallet_command
from codegen.kinds.pallet.keys import KEYS
from codegen.kinds.pallet.program import check_level, file_name, identifiers, pallet_context, task_context
from codegen.kinds.pallet.scene import objects as scene_objects
from codegen.kinds.pallet.section import pallets_of
from codegen.kinds.pallet.verify import FORMS_PER_PALLET
from codegen.protocol import ProgramFile, ProgramKind, ProgramPlan
from codegen.render import program_emitter


class PalletKind(ProgramKind):
    name = "pallet"
    order = 20
    cell_file = KEYS
    target_keys = {
        "files": list,  # a program's files per [[pallet]] ("...{pallet}..."); with `task`, the task's modules too
        "node_files": list,  # a second program per [[pallet]]: the same program in another form (a Script node's)
        "task": bool,  # every pallet's program in one task: its files once, "{pallet}" files once per pallet
        "counters": dict,  # layer and box: the counters' names for --input and verify; holds: the grip flag's
        "kept": dict,  # layer and box: where the program reports the counters, if not in counters
        "store": str,  # where the counters outlive a reload and a regeneration: a file, "plc", "program"
        "store_attribute": str,  # the module attribute the store's file carries (a program load leaves its module)
        "declares": list,  # the words that begin a declaration in the language (after others: LOCAL, GLOBAL)
        "registers": int,  # the first register of the counters, where the controller keeps them in the PLC
        "registers_max": int,  # the last register the counters may use
        "level_only": bool,  # no pose product: a level pallet only
        "joint_blend": bool,  # a joint move may blend into the next (false: it stops at its point)
        "input_stops": bool,  # reading an input stops the advance run: the move before a check ends exactly
        "asks": bool,  # the program can ask the operator Yes/No (after a stop during a release: is the item down?)
    }

    @classmethod
    def parse_section(cls, ctx, data: dict, cell):
        return checked_pallets(ctx, data, cell) or None

    @classmethod
    def standalone(cls, data: dict) -> bool:
        return bool(data.get("pallet"))

    @classmethod
    def check_cell(cls, ctx, cell) -> None:
        if pallets_of(cell) and (cell.io is None or not cell.io.feedback):
            ctx.fail(
                "cell.io", "a cell with [[pallet]] needs [cell.io] with feedback: the gripper's output and its sensor"
            )

    @classmethod
    def programs(cls, cell, target) -> list[ProgramPlan]:
        """Each [[pallet]]'s program: "pal_<name>.src" from the template "kinds/pallet.src.j2" (a data list, a
        Script-node twin); where the target runs them in one task, one program of every pallet's module."""
        pallets = pallets_of(cell)
        if not pallets:
            return []
        facts = cls.facts(target)
        if facts.get("task") and cell.stations:
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
            return [ProgramPlan(cls.name, ident, tuple(out), task_context(cell, target, emitter, contexts), 0)]
        plans = []
        forms = [facts["files"], *([facts["node_files"]] if "node_files" in facts else [])]
        for index, context in enumerate(contexts):
            for form, patterns in enumerate(forms):
                own = files(patterns, index)
                ident = own[0].name.split(".")[0]
                number = FORMS_PER_PALLET * index + form
                plans.append(ProgramPlan(cls.name, ident, tuple(own), {"pallet": context}, number))
        return plans

    @classmethod
    def reach(cls, cell, targets: list[str]) -> list:
        return reach.check(cell, targets)

    @classmethod
    def identities(cls, check) -> list:
        from codegen.kinds.pallet import derivation  # sympy: only `codegen derive` pays for it

        return [*derivation.pallet_identities(check), *derivation.box_pose_identities(check)]

    # --- verify -------------------------------------------------------------------------------
    report_key = "pallets"
    scenarios = verify.SCENARIOS

    @classmethod
    def printed_blocks(cls) -> dict:
        from codegen.kinds.pallet.derivation import level_box_position  # sympy: only the derivation pays

        box_px, box_py = level_box_position()
        return {"box": {"box_px": box_px, "box_py": box_py}}

    @classmethod
    def verify_cases(cls, cell, source, count: int, seed: int) -> list:
        return verify.verify_cases(cell, source, seed)

    @classmethod
    def setup(cls, cell, source, case):
        return verify.setup(cell, source, case)

    @classmethod
    def judge(cls, cell, source, case, trace, setup):
        return verify.judge(cell, source, case, trace)

    @classmethod
    def describe(cls, cell, case) -> str:
        run = case.data
        pallet = "" if run.pallet < 0 else f"pallet {pallets_of(cell)[run.pallet].name} "
        return f"{pallet}layer {run.case.layer} box {run.case.box}"

    @classmethod
    def new_figures(cls):
        return verify.PalletFigures()

    @classmethod
    def add_figures(cls, figures, case, judged) -> None:
        figures.boxes += judged

    @classmethod
    def merge_figures(cls, into, part) -> None:
        into.boxes += part.boxes

    @classmethod
    def summary(cls, row) -> dict:
        return {"boxes_placed": 0 if row.figures is None else row.figures.boxes}

    @classmethod
    def legacy_summary(cls, row) -> dict:
        return verify.legacy_summary(row)

    @classmethod
    def report_lines(cls, rows: list) -> list[str]:
        return verify.report_lines(rows)

    @classmethod
    def scene(cls, cell) -> list[dict]:
        return scene_objects(cell, cls.section(cell) or ())

    @classmethod
    def commands(cls) -> list:
        return [(None, pallet_command)]
