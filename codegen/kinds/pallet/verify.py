"""Verify stacking programs: each case's setup and the float64 reference's moves, outputs and counters as the plan."""

from __future__ import annotations

import random
from dataclasses import dataclass, replace

import numpy as np

from codegen.controllers import get_target
from codegen.emit import Emitter
from codegen.kinds.pallet.cycle import PalletCase, cases, expected
from codegen.kinds.pallet.facts import facts
from codegen.kinds.pallet.program import counter_names, counter_registers
from codegen.kinds.pallet.reach import configurations, joints_of
from codegen.kinds.pallet.section import pallets_of
from codegen.model.io import LATE_SHARE, signal_name
from codegen.reference import home_move
from codegen.robot.expect import tool_inputs
from codegen.robot.taught import ReachError
from codegen.sim.gripper import Gripper
from codegen.verify.plan import (
    START_AWAY_DEG,
    Case,
    Expectation,
    Judgement,
    PlannedMove,
    PlannedOutput,
    Setup,
    Stored,
    refuses_start,
)

# A pallet case's category -> the scenario it runs (codegen.verify.plan.SCENARIOS; the others are its own)
SCENARIO_OF = {
    "gripper_silent": "gripper_silent",
    "gripper_stuck_at_target": "gripper_stuck",
    "gripper_stuck_at_q": "gripper_stuck",
    "gripper_late": "device_late",
    "bad_counters": "reading_out_of_range",
    "start_away": "start_away",
    "start_mid_cycle": "start_mid_cycle",
}
SCENARIOS = {
    "start_away": "",
    "start_mid_cycle": "",
    "gripper_silent": "",
    "gripper_stuck": "",
    "device_late": "",  # the gripper confirms late, within its timeout
    "device_silent": "its one device is the gripper: gripper_silent and gripper_stuck are its silences",
    "reading_out_of_range": "",  # the counters the cell PLC or the operator set, out of the stack
}


def verify_cases(cell, index: int, seed: int) -> list[Case]:
    """The pallet's cases (codegen/kinds/pallet/cycle.py) and the common ones made from its first: the gripper
    late within its timeout, the arm away from home, the arm where a stopped cycle left it (at a box's target)."""
    pallet = pallets_of(cell)[index]
    own = cases(pallet, random.Random(seed))
    first = own[0]
    extra = [
        replace(first, category="gripper_late", gripper="late"),
        replace(first, category="start_away"),
        replace(first, category="start_mid_cycle"),
    ]
    return [Case(c.category, c, SCENARIO_OF.get(c.category, c.category), _start(c.category)) for c in own + extra]


def _start(category: str) -> str:
    return {"start_away": "away", "start_mid_cycle": "mid_cycle"}.get(category, "home")


def setup(cell, index: int, target_name: str, case: Case) -> Setup:
    target, pallet_case = get_target(target_name), case.data
    layer_name, box_name = counter_names(target, index)
    output = signal_name(target, "output", cell.io.output[target_name])
    feedback = signal_name(target, "input", cell.io.feedback[target_name])
    late = LATE_SHARE * cell.io.timeout_s
    gripper = Gripper(output, feedback, cell.io.value, pallet_case.gripper, late)
    return Setup(
        {layer_name: pallet_case.layer, box_name: pallet_case.box, **tool_inputs(cell, target_name)},
        (gripper,),
        {feedback: pallet_case.closed},
        _start_joints(cell, index, target_name, case),
        kept_names(target, index),
    )


def _start_joints(cell, index: int, target_name: str, case: Case):
    home = home_move(cell, target_name)
    if home is None:
        return None
    if case.start == "away":
        return home[1] + np.array(START_AWAY_DEG)
    if case.start == "mid_cycle":  # where a stopped cycle leaves the arm: at its first box's target, released
        want = expected(cell, pallets_of(cell)[index], case.data)
        target_move = next(i for i, m in enumerate(want.moves) if m.name.endswith("target"))
        named = configurations(cell, pallets_of(cell)[index], target_name)
        return joints_of(cell, target_name, want.moves, "restart", pallets_of(cell)[index], named)[target_move]
    return np.asarray(cell.robot.home[target_name], dtype=float)


def kept_names(target, index: int) -> tuple[str, str]:
    """Where the run leaves the counters: the program's own persistent variables, or the outputs it reports
    them in (the [program.pallet] table's `kept`)."""
    names = facts(target).get("kept")
    if names is None:
        return counter_names(target, index)
    registers = counter_registers(target, index)
    return names["layer"].format(layer=registers[0]), names["box"].format(box=registers[1])


def judge(cell, index: int, target_name: str, case: Case) -> Judgement:
    """The reference's moves (home first, with an arm), the gripper's outputs and the counters at the end; a
    start away from home or mid-cycle: the target's restart rule (refused at home-only targets)."""
    pallet, target = pallets_of(cell)[index], get_target(target_name)
    pallet_case: PalletCase = case.data
    want = expected(cell, pallet, pallet_case)
    home = home_move(cell, target_name)
    message = refuses_start(cell, target, case)
    layer_name, box_name = kept_names(target, index)
    start_counters = (pallet_case.layer, pallet_case.box)
    if message is not None:
        stored = _stored(layer_name, box_name, start_counters, start_counters)
        return Judgement([Expectation(message, (), (), stored)])
    output = signal_name(target, "output", cell.io.output[target_name])
    moves = list(want.moves)
    outputs = [PlannedOutput(output, value, after, "gripper") for value, after in want.outputs]
    planned = [PlannedMove(m.name, m.kind, m.tcp2base, m.exact, m.speed_mm_s, 0.0, _percent(cell, m)) for m in moves]
    planned_joints = None
    if home is not None and (moves or outputs):  # with an arm the program goes home first
        planned.insert(
            0,
            PlannedMove(
                "home", home[0].kind, home[0].tcp2base, True, None, 0.0, _percent(cell, home[0]), joints=home[1]
            ),
        )
        outputs = [replace(o, after_moves=o.after_moves + 1) for o in outputs]

        def planned_joints() -> list | None:  # by the controller's rule, with the configurations the program names
            try:
                named = configurations(cell, pallet, target_name)
                return [home[1], *joints_of(cell, target_name, moves, "verify", pallet, named)]
            except ReachError:
                return None

    message = None if want.halt is None else Emitter(target).string(want.halt)
    stored = _stored(layer_name, box_name, want.counters, start_counters)
    boxes = sum(1 for m in moves if m.name.endswith("target"))
    expectation = Expectation(message, tuple(planned), tuple(outputs), stored, planned_joints=planned_joints)
    return Judgement([expectation], figures=boxes)


def _percent(cell, move) -> float | None:
    return cell.motion.joint_speed_percent if move.kind == "joint" else None


def _stored(layer_name: str, box_name: str, counters: tuple[int, int], start: tuple[int, int]) -> tuple:
    """The counters where the program keeps them when it ends (a name never written: the start value stays)."""
    return (
        Stored(layer_name, counters[0], 0.0, "the layer counter", start[0]),
        Stored(box_name, counters[1], 0.0, "the box counter", start[1]),
    )


@dataclass
class PalletFigures:
    boxes: int = 0  # boxes placed (or taken) over the passing cases


def legacy_summary(row) -> dict:
    """A row as `codegen verify --json` lists it under "pallets"."""
    s = row.summary()
    return {
        "target": row.target,
        "pallet": row.program,
        "files": row.files,
        "cases": row.cases,
        "mismatches": row.mismatches,
        "boxes_placed": 0 if row.figures is None else row.figures.boxes,
        "pos_max_mm": s["position_error_mm"]["max"],
        "rot_max_deg": s["orientation_error_deg"]["max"],
        "cases_per_s": s["cases_per_second"],
        "first_mismatches": row.first_mismatches,
    }


def report_lines(rows: list) -> list[str]:
    lines = ["pallet program          target    cases  fail  boxes"]
    for r in rows:
        boxes = 0 if r.figures is None else r.figures.boxes
        lines.append(f"{r.program[:23]:23} {r.target:8} {r.cases:6d} {r.mismatches:5d} {boxes:6d}")
    return lines


__all__ = ["SCENARIOS", "PalletFigures", "judge", "legacy_summary", "report_lines", "setup", "verify_cases"]
