"""Palletizing (source 004) as a program kind: the [[pallet]] tables, a stacking program per pallet and target."""

from __future__ import annotations

from codegen.kinds.pallet import reach, verify
from codegen.kinds.pallet.analysis import checked_pallets
from codegen.kinds.pallet.commands import pallet as pallet_command
from codegen.kinds.pallet.keys import KEYS
from codegen.kinds.pallet.program import check_level, pallet_context, pallet_file_names, pallet_identifiers
from codegen.kinds.pallet.scene import objects as scene_objects
from codegen.kinds.pallet.section import pallets_of
from codegen.protocol import ProgramFile, ProgramKind, ProgramPlan
from codegen.render import program_emitter


class PalletKind(ProgramKind):
    name = "pallet"
    order = 20
    cell_file = KEYS
    target_keys = {
        "files": list,  # a stacking program's files per [[pallet]] ("...{pallet}...")
        "counters": dict,  # layer and box: the counters' names for --input and verify
        "kept": dict,  # layer and box: where the program reports the counters, if not in counters
        "registers": int,  # the first register of the counters, where the controller keeps none
        "registers_max": int,  # the last register the counters may use
        "level_only": bool,  # no pose product: a level pallet only
    }

    @classmethod
    def parse_section(cls, ctx, data: dict, cell):
        return checked_pallets(ctx, data, cell.pose_format) or None

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
        """Each [[pallet]]'s stacking program: "pal_<name>.src" from the template "kinds/pallet.src.j2"."""
        pallets = pallets_of(cell)
        if not pallets:
            return []
        emitter = program_emitter(cell, target)
        out = []
        for index, (pallet, ident) in enumerate(zip(pallets, pallet_identifiers(cell, target), strict=True)):
            check_level(pallet, target)
            context = pallet_context(cell, pallet, index, ident, target, emitter)
            names = pallet_file_names(target, context["ident"])
            files = tuple(
                ProgramFile(file_name, f"{target.name}/kinds/{pattern.format(pallet='pallet')}.j2")
                for pattern, file_name in zip(cls.facts(target)["files"], names, strict=True)
            )
            out.append(ProgramPlan(cls.name, context["ident"], files, {"pallet": context}, index))
        return out

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
        return verify.verify_cases(cell, source.index, seed)

    @classmethod
    def setup(cls, cell, source, case):
        return verify.setup(cell, source.index, source.target, case)

    @classmethod
    def judge(cls, cell, source, case, trace, setup):
        return verify.judge(cell, source.index, source.target, case)

    @classmethod
    def describe(cls, cell, case) -> str:
        return f"layer {case.data.layer} box {case.data.box}"

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
