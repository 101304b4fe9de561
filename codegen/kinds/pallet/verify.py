"""Verify stacking programs: each case run in the interpreter against the float64 reference."""

from __future__ import annotations

import math
import random
import time
from dataclasses import dataclass, field, replace

import numpy as np

from codegen.controllers import get_target
from codegen.dialects import get_dialect
from codegen.emit import Emitter
from codegen.kinds.pallet.cycle import ExpectedMove, PalletCase, cases, expected
from codegen.kinds.pallet.program import counter_names, counter_registers, pallet_identifiers
from codegen.kinds.pallet.reach import configurations, joints_of
from codegen.kinds.pallet.section import facts, pallets_of
from codegen.model.cell import Cell
from codegen.model.io import signal_name
from codegen.robot.expect import arm_of, home_move
from codegen.sections import Reports
from codegen.sim.gripper import Gripper
from codegen.verify import TOLERANCES, _pose_errors, tally

JOINT_TOL_DEG = 0.01  # the controller's choice against the plan: float32 poses, the same rule


@dataclass
class PalletReport:
    target: str
    pallet: str
    files: list[str]
    cases: int = 0
    mismatches: int = 0
    boxes: int = 0  # boxes placed over all cases
    first_mismatches: list[str] = field(default_factory=list)
    max_pos_mm: float = 0.0
    max_rot_deg: float = 0.0
    seconds: float = 0.0

    def summary(self) -> dict:
        return {
            "target": self.target,
            "pallet": self.pallet,
            "files": self.files,
            "cases": self.cases,
            "mismatches": self.mismatches,
            "boxes_placed": self.boxes,
            "pos_max_mm": self.max_pos_mm,
            "rot_max_deg": self.max_rot_deg,
            "cases_per_s": self.cases / self.seconds if self.seconds > 0 else None,
            "first_mismatches": self.first_mismatches,
        }


def compare(cell: Cell, target, index: int, case: PalletCase, want, got) -> tuple[str | None, float, float]:
    """(problem or None, largest position error mm, largest orientation error deg)."""
    pos_tol, rot_tol = TOLERANCES[target.numbers]
    worst_pos = worst_rot = 0.0
    if want.halt is not None and not got.halted:
        return f"expected the stop {want.halt!r}, the program did not stop ({len(got.moves)} moves)", 0.0, 0.0
    message = None if want.halt is None else Emitter(target).string(want.halt)  # as the program can write it
    if message is not None and got.halt_message != message:
        return f"stop message {got.halt_message!r}, expected {message!r}", 0.0, 0.0
    if want.halt is None and got.halted:
        return f"unexpected stop: {got.halt_message!r}", 0.0, 0.0
    if len(got.moves) != len(want.moves):
        return f"{len(got.moves)} moves, expected {len(want.moves)}", 0.0, 0.0
    dialect = get_dialect(target.dialect)
    for i, (g, e) in enumerate(zip(got.moves, want.moves, strict=True)):
        if g.kind != e.kind:
            return f"move {i + 1} ({e.name}, line {g.line}) is {g.kind}, expected {e.kind}", worst_pos, worst_rot
        own_tool = cell.robot is not None and cell.robot.tool_given  # the program's tooldata, not tool0
        settings = dialect.move_settings(
            target.program, e.kind, e.exact, own_tool, e.speed_mm_s, 0.0, cell.motion.joint_speed_percent
        )
        for key, value in settings.items():
            have = g.settings.get(key)
            close = isinstance(value, float) and isinstance(have, float) and math.isclose(have, value, rel_tol=1e-6)
            if have != value and not close:
                return f"move {i + 1} ({e.name}, line {g.line}): {key} {have}, expected {value}", worst_pos, worst_rot
        pos, rot = _pose_errors(g.tcp2base.tolist(), e.tcp2base.tolist())
        worst_pos, worst_rot = max(worst_pos, pos), max(worst_rot, rot)
        if not (pos <= pos_tol and rot <= rot_tol):
            return (
                f"move {i + 1} ({e.name}, line {g.line}): position error {pos:.6f} mm, orientation error "
                f"{rot:.6f} deg (tolerance {pos_tol} mm, {rot_tol} deg)",
                worst_pos,
                worst_rot,
            )
    output = signal_name(target, "output", cell.io.output[target.name])
    events = [o for o in got.outputs if o.name == output]
    have = [(o.value, o.after_moves) for o in events]
    if have != list(want.outputs):
        problem = f"gripper output {output}: {have}, expected {list(want.outputs)} (value, moves before)"
        return problem, worst_pos, worst_rot
    moving = [o for o in events if o.moving]
    if moving:
        return f"gripper output {output} set at line {moving[0].line} while the arm moves", worst_pos, worst_rot
    layer, box = (got.kept[name] for name in kept_names(target, index))
    kept = (case.layer if layer is None else layer, case.box if box is None else box)
    if kept != want.counters:
        problem = (
            f"the counters end at layer {kept[0]} box {kept[1]}, "
            f"expected layer {want.counters[0]} box {want.counters[1]}"
        )
        return problem, worst_pos, worst_rot
    return None, worst_pos, worst_rot


def with_home(cell: Cell, target_name: str, want):
    """With an arm the program goes home first (in joints, after its counter checks): the home move
    before the cycle's moves, and every gripper output one move later."""
    home = home_move(cell, target_name)
    if home is None or not (want.moves or want.outputs):  # no arm, or a stop before any move
        return want
    move = ExpectedMove(home[0].kind, home[0].tcp2base, "home", None, True)
    outputs = tuple((value, after + 1) for value, after in want.outputs)
    return replace(want, moves=(move, *want.moves), outputs=outputs)


def joints_problem(cell: Cell, target_name: str, want, got, pallet, named) -> str | None:
    """Where the controller's choice of each move's joints (the interpreter's arm) differs from the
    generate-time plan (codegen/pallet/reach.py, with the configurations the program names): a
    configuration the proof did not cover."""
    planned = joints_of(cell, target_name, want.moves, "verify", pallet, named)
    for i, (g, q) in enumerate(zip(got.moves, planned, strict=True)):
        if g.joints is None or np.max(np.abs(np.asarray(g.joints) - q)) > JOINT_TOL_DEG:
            have = None if g.joints is None else np.asarray(g.joints).round(3).tolist()
            return f"move {i + 1} ({want.moves[i].name}, line {g.line}): joints {have}, planned {q.round(3).tolist()}"
    return None


def kept_names(target, index: int) -> tuple[str, str]:
    """Where the run leaves the counters: the program's own persistent variables, or the outputs it reports
    them in (targets/<t>.toml pallet_kept; a value never written: the counters did not change)."""
    names = facts(target).get("kept")
    if names is None:
        return counter_names(target, index)
    registers = counter_registers(target, index)
    return names["layer"].format(layer=registers[0]), names["box"].format(box=registers[1])


def verify_pallet(
    cell: Cell, index: int, target_name: str, program, files: list[str], seed: int = 0, first_only: bool = False
) -> PalletReport:
    """Every case of pallet `index` on one target's program (first_only: stop at the first mismatch)."""
    pallet, target = pallets_of(cell)[index], get_target(target_name)
    layer_name, box_name = counter_names(target, index)
    output = signal_name(target, "output", cell.io.output[target.name])
    feedback = signal_name(target, "input", cell.io.feedback[target.name])
    report = PalletReport(target_name, pallet.name, files)
    start = time.perf_counter()
    named = configurations(cell, pallet, target_name)
    for case in cases(pallet, random.Random(seed)):
        want = with_home(cell, target_name, expected(cell, pallet, case))
        gripper = Gripper(output, feedback, cell.io.value, case.gripper)
        try:
            arm = arm_of(cell, target_name)  # the arm solves every move by the controller's rules
            got = program.run(
                {layer_name: case.layer, box_name: case.box},
                devices=(gripper,),
                signals={feedback: case.closed},
                keep=kept_names(target, index),
                arm=arm,
                start_joints=None if arm is None else cell.robot.home[target_name],
            )
            problem, pos, rot = compare(cell, target, index, case, want, got)
            if problem is None and arm is not None:
                problem = joints_problem(cell, target_name, want, got, pallet, named)
        except Exception as exc:  # a run error is this case's mismatch
            problem, pos, rot = f"run error: {exc}", 0.0, 0.0
        report.boxes += sum(1 for m in want.moves if m.name.endswith("target"))
        if tally(report, problem, pos, rot, f"{case.category} layer {case.layer} box {case.box}") and first_only:
            break
    report.seconds = time.perf_counter() - start
    return report


def fresh_pallet_programs(cell: Cell, target_name: str) -> list[tuple[object, list[str]]]:
    """Each pallet's program, rendered and parsed: (program, file names)."""
    from codegen.kinds.pallet.program import pallet_file_names
    from codegen.render import render
    from codegen.verify_runs import load_program

    target = get_target(target_name)
    files = {f.relpath.rsplit("/", 1)[1]: f for f in render(cell, [target_name])}
    out = []
    for ident in pallet_identifiers(cell, target):
        names = pallet_file_names(target, ident)
        main = files[names[0]]
        companions = {"." + n.rsplit(".", 1)[1]: files[n].text for n in names[1:]}
        out.append((load_program(target, main.text, f"<fresh>/{main.relpath}", companions), names))
    return out


def verify_cell_pallets(cell: Cell, targets: list[str], files: list | None = None, seed: int = 0) -> list[PalletReport]:
    """Every pallet on every target: fresh programs, or the given program files whose names are a
    pallet's program (files: paths; the others are not pallet programs and are left to the caller)."""
    from codegen.kinds.pallet.program import pallet_file_names
    from codegen.verify_runs import file_source

    reports = []
    for name in targets:
        target = get_target(name)
        idents = pallet_identifiers(cell, target)
        if files is None:
            programs = fresh_pallet_programs(cell, name)
            reports += [verify_pallet(cell, i, name, p, f, seed) for i, (p, f) in enumerate(programs)]
            continue
        for path in files:
            for i, ident in enumerate(idents):
                if path.name == pallet_file_names(target, ident)[0]:
                    source = file_source(name, path)
                    reports.append(verify_pallet(cell, i, name, source.load(), list(source.files), seed))
    return reports


def report_lines(reports: list[PalletReport]) -> list[str]:
    lines = ["pallet    target    cases  fail  boxes  pos max mm  rot max deg  cases/s"]
    for r in reports:
        rate = f"{r.cases / r.seconds:7.0f}" if r.seconds > 0 else "      -"
        lines.append(
            f"{r.pallet[:9]:9} {r.target:8} {r.cases:6d} {r.mismatches:5d} {r.boxes:6d}  "
            f"{r.max_pos_mm:10.2e}  {r.max_rot_deg:11.2e}  {rate}"
        )
        lines += [f"  {r.target}: {m}" for m in r.first_mismatches]
    return lines


def is_pallet_program(cell: Cell, path) -> bool:
    """A pallet's program file or one of its companions (a data file is read with its program)."""
    from codegen.kinds.pallet.program import pallet_file_names

    for name in cell.targets:
        target = get_target(name)
        if any(path.name in pallet_file_names(target, ident) for ident in pallet_identifiers(cell, target)):
            return True
    return False


@dataclass
class PalletSection(Reports):
    """`codegen verify`'s part for the stacking programs; alone: the cell (or the files given) has nothing else."""

    cell: Cell
    reports: list[PalletReport]
    alone: bool

    def lines(self) -> list[str]:
        verdict = "all stacking traces match the reference" if self.ok else "MISMATCHES in the stacking programs"
        return [*report_lines(self.reports), f"verify: {verdict}"]

    def finish(self, as_json: bool) -> None:
        """Report and exit (0: every case matched)."""
        import json
        import sys

        import click

        if as_json:
            click.echo(json.dumps({"cell": self.cell.name, "ok": self.ok, "pallets": self.summaries()}, indent=2))
        else:
            for line in self.lines():
                click.echo(line)
        sys.exit(0 if self.ok else 1)


class PalletFilesError(ValueError):
    """Files given to verify that hold no pallet program for the targets asked."""


def pallet_section(cell: Cell, files: tuple, targets: tuple, seed: int) -> tuple[PalletSection | None, tuple]:
    """The pallet programs among FILES (or fresh ones) verified; the other files are returned."""
    from pathlib import Path

    if not pallets_of(cell):
        return None, files
    mine = [Path(f) for f in files if is_pallet_program(cell, Path(f))]
    rest = tuple(f for f in files if Path(f) not in mine)
    names = list(targets) or list(cell.targets)
    reports = verify_cell_pallets(cell, names, mine if files else None, seed)  # RunError: cannot load
    if files and mine and not reports:
        raise PalletFilesError(
            "no pallet program among the files for the targets asked: a data file is read with its program "
            "(give the program), and --target must be the program's"
        )
    return PalletSection(cell, reports, alone=not cell.stations or (bool(files) and not rest)), rest
