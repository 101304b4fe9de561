"""Conveyor tracking (source 002) as a program kind: the [conveyor] table, its calibration, a pick-from-belt program."""

from __future__ import annotations

from codegen.kinds.conveyor import budget, reach, verify
from codegen.kinds.conveyor.commands import calibrate_conveyor
from codegen.kinds.conveyor.keys import KEYS
from codegen.kinds.conveyor.pick import check_inputs
from codegen.kinds.conveyor.program import conveyor_context, conveyor_file_names, picks_on
from codegen.kinds.conveyor.scene import objects as scene_objects
from codegen.kinds.conveyor.section import conveyor_of, parse_conveyor
from codegen.protocol import ProgramFile, ProgramKind, ProgramPlan
from codegen.render import program_emitter


class ConveyorKind(ProgramKind):
    name = "conveyor"
    order = 30
    cell_file = KEYS
    target_keys = {
        "files": list,  # the pick-from-belt program of a cell with [conveyor.pick]
        "registers": dict,  # the part queue's registers by role (seq, count, x, z, ack, stop)
        "names": dict,  # the same by the names devices and `codegen run --input` use
        "signals": dict,  # the queue as groups of digital signals (ranges of numbered signals, or named signals)
        "encoder_inputs": list,  # the lowest and highest digital input an encoder's A and B may use
        "tracking": list,  # how the pick program follows the belt: "native", "intercept"
        "blends": dict,  # per tracking mode, the moves the program blends into the next (plan.py)
        "unit": str,  # native (ABB): the belt's mechanical unit unless the cell names another
        "units": list,  # native (ABB): the mechanical units a cell may name for its belt
        "unit_signals": dict,  # native (ABB): the tracking option's signals the program uses
        "timers": int,  # intercept: how many numbered timers ([conveyor.pick] timer gives the program one)
        "timer_s": float,  # intercept: the numbered timers' unit (a time measured is off by up to one)
        "path_acc_m_s2": float,  # the path acceleration the program sets for its straight moves (the descent's ramp)
        "trigger": float,  # native (UR): the frame (s) a thread latches the robot's own encoder at the trigger in
    }

    @classmethod
    def parse_section(cls, ctx, data: dict, cell):
        return parse_conveyor(ctx, data, cell.targets, cell.pose_format)

    @classmethod
    def standalone(cls, data: dict) -> bool:
        return isinstance(data.get("conveyor"), dict) and "pick" in data["conveyor"]

    @classmethod
    def check_cell(cls, ctx, cell) -> None:
        conveyor = conveyor_of(cell)
        if conveyor is not None and conveyor.pick is not None and (cell.io is None or not cell.io.feedback):
            ctx.fail("cell.io", "a cell with [conveyor.pick] needs [cell.io] with feedback: the gripper and its sensor")
        if conveyor is not None and conveyor.pick is not None:
            check_inputs(ctx, conveyor.pick, cell.io.feedback)
        budget.check(ctx, cell)

    @classmethod
    def programs(cls, cell, target) -> list[ProgramPlan]:
        """The pick-from-belt program of a cell with [conveyor.pick]: "cnv_<cell>.script" from the template
        "kinds/conveyor.script.j2"."""
        if not picks_on(cell, target):
            return []
        context = conveyor_context(cell, target, program_emitter(cell, target))
        files = tuple(
            ProgramFile(name, f"{target.name}/kinds/{pattern.format(conveyor='conveyor')}.j2")
            for pattern, name in zip(cls.facts(target)["files"], conveyor_file_names(cell, target), strict=True)
        )
        return [ProgramPlan(cls.name, context["ident"], files, {"conveyor": context})]

    @classmethod
    def reach(cls, cell, targets: list[str]) -> list:
        return reach.check(cell, targets)

    # --- verify -------------------------------------------------------------------------------
    report_key = "conveyors"
    scenarios = verify.SCENARIOS

    @classmethod
    def verify_cases(cls, cell, source, count: int, seed: int) -> list:
        return verify.cases(cell, seed)

    @classmethod
    def setup(cls, cell, source, case):
        return verify.setup(cell, source.target, case)

    @classmethod
    def judge(cls, cell, source, case, trace, setup):
        return verify.judge(cell, source.target, case, trace, setup)

    @classmethod
    def new_figures(cls):
        return verify.BeltFigures()

    @classmethod
    def add_figures(cls, figures, case, judged) -> None:
        figures.picked += judged[0]
        figures.skipped += judged[1]

    @classmethod
    def merge_figures(cls, into, part) -> None:
        into.picked += part.picked
        into.skipped += part.skipped

    @classmethod
    def summary(cls, row) -> dict:
        figures = row.figures or verify.BeltFigures()
        return {"parts_picked": figures.picked, "parts_skipped": figures.skipped}

    @classmethod
    def legacy_summary(cls, row) -> dict:
        return verify.legacy_summary(row)

    @classmethod
    def report_lines(cls, rows: list) -> list[str]:
        return verify.report_lines(rows)

    @classmethod
    def scene(cls, cell) -> list[dict]:
        return [] if cls.section(cell) is None else scene_objects(cell, cls.section(cell))

    @classmethod
    def commands(cls) -> list:
        return [("calibrate", calibrate_conveyor)]
