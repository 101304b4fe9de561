"""`codegen run`: one program in the interpreter, with the simulated vision PC, gripper and arm."""

from __future__ import annotations

import re
import sys
from contextlib import suppress
from pathlib import Path

import click

from codegen.cli_base import Number, UserError, file_target_option, main, step_limit_option
from codegen.cli_base import dump as _dump
from codegen.csvfile import number, whole

START_JOINT_MAX_DEG = 3600  # ten turns: beyond any arm's axis range (a typing error, not a joint)


def _parse_input(text: str):
    """NAME=VALUE: a whole number, a number or comma-separated numbers (a record), in decimal digits and finite as
    every numeric option (no nan, inf or 1e999: no controller's input holds them)."""
    name, sep, value = text.partition("=")
    if not sep or not name:
        raise UserError(f"--input: expected NAME=VALUE, got {text!r}")
    if "," in value:  # a record such as BASE_DATA[1]=X,Y,Z,A,B,C
        try:
            return name, tuple(number(v) for v in value.split(","))
        except ValueError:
            raise UserError(f"--input {name}: not finite numbers in decimal digits: {value!r}") from None
    try:
        return name, whole(value)
    except ValueError:
        pass
    try:
        return name, number(value)
    except ValueError:
        raise UserError(f"--input {name}: not a finite number in decimal digits: {value!r}") from None


def _signal_in_range(target, name: str, where: str) -> None:
    """An input named by its number (the input pattern of targets/<t>.toml [program] signals) lies within the
    controller's range; another name (an alias the program declares, a named signal) is the program's to know."""
    facts = target.program.get("signals") or {}
    if facts.get("form") != "index" or "range" not in facts:
        return
    pattern = re.escape(facts["input"]).replace(re.escape("{n}"), r"(-?\d+)")
    found = re.fullmatch(pattern, name)
    low, high = facts["range"]
    if found is not None and not low <= int(found.group(1)) <= high:
        raise UserError(
            f"{where}: no input {found.group(1)} on {target.title}: its inputs are {facts['input'].format(n=low)} to "
            f"{facts['input'].format(n=high)} (targets/{target.name}.toml)"
        )


def program_files(paths: tuple[str, ...], target_name: str | None):
    """(target, dialect, files as SourceFile) of the paths given: files and folders (every file of a folder, and
    of its subfolders, whose suffix is a language's); the language from --target, else from the suffixes (all
    of one language). A program file given alone brings the data files of its name beside it (a .dat beside
    its .src). Each file is decoded with the language's encodings (dialects/core/files.py read_source)."""
    from codegen.controllers import get_target, target_of_language, target_of_suffix
    from codegen.dialects import dialect_of_suffix, get_dialect
    from codegen.dialects.core.files import read_source
    from codegen.dialects.core.values import RunError

    given: list[Path] = []
    folders = [Path(t) for t in paths if Path(t).is_dir()]
    for text in paths:
        path = Path(text)
        if path.is_dir():
            found = sorted(p for p in path.rglob("*") if p.is_file() and dialect_of_suffix(p.suffix) is not None)
            if not found:
                raise UserError(f"{path}: no program files in this folder")
            given.extend(found)
        else:
            given.append(path)
    if target_name is not None:
        target = get_target(target_name)
        dialect = get_dialect(target.dialect)
        own = dialect.suffixes + dialect.companions + dialect.configurations  # a channel's configuration too
        given = [p for p in given if p.suffix.lower() in own or not any(f in p.parents for f in folders)]
        for path in given:
            if path.suffix.lower() not in own:
                raise UserError(f"{path}: not a file of {target.title} (its files end in {', '.join(own)})")
    else:
        languages: dict[str, Path] = {}
        for path in given:
            found_dialect = dialect_of_suffix(path.suffix)
            if found_dialect is None:
                raise UserError(f"{path}: cannot tell the target from the suffix; use --target")
            languages.setdefault(found_dialect.name, path)
        if len(languages) > 1:
            shown = ", ".join(f"{path.name} ({name})" for name, path in languages.items())
            raise UserError(f"files of several languages: {shown}; give one program's files or use --target")
        dialect = get_dialect(next(iter(languages)))
        targets = (target_of_suffix(p.suffix) for p in given)
        target = next((t for t in targets if t is not None and t.dialect == dialect.name), None)
        target = target or target_of_language(dialect.name)
        if target is None:
            raise UserError(f"{given[0]}: cannot tell the target from the suffix; use --target")
    if not given:
        raise UserError("no program files of that target among the files given")
    if len(paths) == 1 and not folders and given[0].suffix.lower() in dialect.suffixes:
        try:
            beside = dialect.beside(given[0])  # the data files it brings from its folder
        except RunError as exc:
            raise UserError(str(exc)) from None
        given.extend(p for p in beside if p not in given)
    try:
        files = [read_source(p, dialect.encodings) for p in dict.fromkeys(given)]
    except RunError as exc:
        raise UserError(str(exc)) from None
    return target, dialect, files


def program_groups(dialect, files) -> list[list]:
    """The programs the files make (Dialect.programs: each program file first); a UserError where they make none."""
    from codegen.dialects.core.values import RunError

    try:
        groups = dialect.programs(files)
    except RunError as exc:
        raise UserError(str(exc)) from None
    if not groups:
        raise UserError(f"{files[0].name}: a data file, read together with its program: give the program file too")
    return groups


def load_group(dialect, group, entry: str | None = None):
    """One program from its files (Dialect.load_files), started at the routine entry where given; its load errors
    as one message each (exit 2)."""
    from codegen.dialects.core.values import RunError

    if entry is not None and dialect.entry_routines is None:
        raise UserError(f"--entry {entry}: a {dialect.name} program starts only at its own entry")
    try:
        return dialect.load_files(group) if entry is None else dialect.load_files(group, entry=entry)
    except RecursionError:
        raise UserError(f"{group[0].name}: statements or expressions nested too deeply to run here") from None
    except RunError as exc:
        hint = ""
        if entry is None and dialect.entry_routines and "no PROC main" in str(exc):
            how = dialect.entry_routines
            hint = f" (modules a production program's main calls: start at their routine with --entry NAME, as {how})"
        raise UserError(str(exc) + hint) from None


@main.command()
@click.argument("files", nargs=-1, required=True, type=click.Path(exists=True))
@file_target_option()
@click.option(
    "--input",
    "inputs",
    multiple=True,
    help="Input NAME=VALUE (repeatable): the names are the [program] inputs of targets/<t>.toml.",
)
@click.option(
    "--robot",
    "robot",
    default=None,
    help="The arm (a catalogue model, e.g. 'KR 10 R1100 sixx'): every move is solved to joints by the "
    "controller's rules and checked against the arm's reach and joint limits.",
)
@click.option(
    "--signal",
    "signal_values",
    multiple=True,
    help="A digital input on at the start, NAME=1 (repeatable), as the program names it (the input pattern of "
    "[program] signals in targets/<t>.toml, e.g. standard_digital_in[1]): a gripper's feedback.",
)
@click.option(
    "--gripper",
    "gripper",
    default=None,
    help="A simulated gripper OUTPUT=INPUT (names as the program has them, e.g. '$OUT[17]=$IN[18]'): the "
    "input follows the output after 0.3 s (on when the output is on).",
)
@click.option(
    "--start",
    "start",
    default=None,
    help="Where the arm stands when the program starts: J1,...,J6 in deg (a program that checks it before "
    "it moves, e.g. UR get_actual_joint_positions(), RAPID CJointT(), needs it).",
)
@click.option(
    "--answer",
    "answers",
    multiple=True,
    help="The operator's answer to the next dialog the program shows (repeatable, in order): a softkey's number "
    "or its label, e.g. 'Yes'. Without one, a dialog waiting for an answer stops the run.",
)
@click.option(
    "--entry",
    "entry",
    default=None,
    help="Start at this routine instead of the program's main (RAPID: as after PP to Routine; a global PROC "
    "without parameters, e.g. a module loaded into the production task, which has no main of its own).",
)
@step_limit_option("Stop a runaway program after this many steps (what ran until then is shown).")
@click.option(
    "--max-moves",
    "max_moves",
    type=Number(1, integer=True),
    default=None,
    help="End the run cleanly after this many moves (a cell program that loops for ever), keeping what ran.",
)
@click.option(
    "--max-seconds",
    "max_seconds",
    type=Number(0.0),
    default=None,
    help="End the run cleanly once the program's clock (its moves, waits and sleeps) passes this many seconds.",
)
@click.option(
    "--cell",
    "cell_path",
    default=None,
    type=click.Path(exists=True, dir_okay=False),
    help="A cell file: the program runs on the cell's arm for its target, from the cell's home (unless --start), "
    "and every move is swept against the cell's solids (its floor, machines, fences, each kind's own) and the arm "
    "itself: the first move within the cell's clearance is reported (exit 1), else the least clearance.",
)
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def run(
    files: tuple[str, ...],
    target_name: str | None,
    inputs: tuple[str, ...],
    signal_values: tuple[str, ...],
    gripper: str | None,
    start: str | None,
    robot: str | None,
    answers: tuple[str, ...],
    entry: str | None,
    step_limit: int,
    max_moves: int | None,
    max_seconds: float | None,
    cell_path: str | None,
    as_json: bool,
) -> None:
    """Run one program in the built-in interpreter; print its log, moves (and joints) and how it ended.

    FILES: the program's file, or its files (the modules of a task, a program with its data files), or a
    folder holding them."""
    from codegen.decimals import unsigned_zero
    from codegen.dialects import is_companion
    from codegen.dialects.core.trace import halt_text
    from codegen.dialects.core.values import RunError, StepLimitError
    from codegen.poses import POSE_FORMATS, pose_text, shown_values
    from codegen.sim.gripper import Gripper
    from codegen.sim.operator import Operator
    from codegen.sim.vision_pc import VisionPC

    if len(files) == 1 and is_companion(Path(files[0])):
        raise UserError(f"{files[0]}: a data file, read together with its program: run the program file")
    target, dialect, sources = program_files(files, target_name)
    groups = program_groups(dialect, sources)
    if len(groups) > 1:
        names = ", ".join(g[0].name for g in groups)
        raise UserError(f"these files make {len(groups)} programs ({names}): run one program at a time")
    path = Path(groups[0][0].name)
    values = dict(_parse_input(i) for i in inputs)
    gripper_names = None
    if gripper is not None:
        output, sep, feedback = gripper.partition("=")
        if not sep or not output.strip() or not feedback.strip():
            raise UserError(f"--gripper {gripper!r}: expected OUTPUT=INPUT")
        gripper_names = (output.strip(), feedback.strip())
    joints = None
    if start is not None:
        try:
            joints = [number(v) for v in start.split(",")]
        except ValueError:
            joints = []
        if len(joints) != 6 or not all(abs(v) <= START_JOINT_MAX_DEG for v in joints):
            raise UserError(
                f"--start {start!r}: expected six joint angles J1,...,J6 in deg, each within +-{START_JOINT_MAX_DEG:,}"
            )
    on = {}
    for item in signal_values:
        name, sep, value = item.partition("=")
        if not sep or not name.strip() or value.strip() not in ("0", "1"):
            raise UserError(f"--signal {item!r}: expected NAME=0 or NAME=1")
        on[name.strip()] = value.strip() == "1"
        _signal_in_range(target, name.strip(), f"--signal {item!r}")
    arm = None
    if robot is not None:
        from codegen.robot.arms import catalogue, find_arm

        arm = find_arm(robot)
        if arm is None:
            raise UserError(f"--robot {robot!r}: not in the catalogue; it has: {', '.join(catalogue())}")
        if arm.vendor != target.vendor:
            where = f"--robot {robot!r}"
            raise UserError(f"{where}: an arm of the {arm.vendor} controller; this program is for {target.name}")
    check = None
    if cell_path is not None:
        arm, check = _cell_check(cell_path, target, path.name, robot)
        if joints is None:
            joints = [float(v) for v in check.home]
    program = load_group(dialect, groups[0], entry)
    try:
        unknown = program.unknown_inputs(values)
    except RunError as exc:  # the program's data, set up once before its runs, fails
        raise UserError(str(exc)) from None
    if unknown:
        names = [*target.program["inputs"].values(), *target.program.get("photo", {}).values()]
        raise UserError(
            f"--input {unknown[0]}: {path} has no such variable or register; its vision interface reads "
            f"{', '.join(names)} (any global variable of the program may be set)"
        )
    try:
        # the vision PC answers the program's request to read the station with the --input values
        reading = {name: values[name] for name in target.program["inputs"].values() if name in values}
        devices = [VisionPC.for_target(target, reading)]
        if gripper is not None:
            devices.append(Gripper(*gripper_names))
        if answers:
            devices.append(Operator(answers))
        trace = program.run(
            values,
            step_limit=step_limit,
            devices=devices,
            arm=arm,
            signals=on,
            start_joints=joints,
            max_moves=max_moves,
            max_seconds=max_seconds,
        )
        failure = None
    except RunError as exc:
        trace, failure = getattr(exc, "trace", None), exc
        if trace is None:
            click.echo(f"error: {exc}", err=True)
            sys.exit(1)
        with suppress(RunError):  # the joints of the moves made, where the controller's rules give them
            exc.solve_joints()
        if isinstance(exc, StepLimitError):
            trace.ended = f"{exc}: raise --step-limit, or end the run with --max-moves or --max-seconds"
    swept = None if check is None else check.check(trace, joints, _held(check, on))
    native = POSE_FORMATS[target.pose_format][2]
    moves = [
        {
            "motion": m.kind,
            "line": m.line,
            "pose": None if m.tcp2base is None else list(shown_values(native(m.tcp2base), target.pose_format)),
            "tcp2base": None if m.tcp2base is None else m.tcp2base.tolist(),
            "joints": None if m.joints is None else [round(float(v), 6) for v in m.joints],
        }
        for m in trace.moves
    ]
    if as_json:
        _dump(
            {
                "file": str(path),
                "files": [f.name for f in groups[0]],
                "target": target.name,
                "inputs": values,
                "messages": trace.messages,
                "moves": moves,
                "outputs": [{"name": o.name, "value": o.value, "line": o.line, "time": o.time} for o in trace.outputs],
                "halted": trace.halted,
                "halt_message": trace.halt_message,
                "ended": trace.ended,
                "error": None if failure is None else str(failure),
                "simulated_io": trace.simulated,
                "warnings": trace.warnings,
                "clock_s": round(trace.clock, 6),
                "steps": trace.steps,
                **({} if check is None else {"clearance": _clearance_json(*swept, check.clearance)}),
            }
        )
        if failure is not None or (swept is not None and swept[1] is not None):
            sys.exit(1)
        return
    for message in trace.messages:
        click.echo(f"message: {message}")
    for m in moves:
        shown = "(a joint position)" if m["pose"] is None else pose_text(m["pose"], target.pose_format)
        joints = "" if m["joints"] is None else "  joints " + " ".join(unsigned_zero(f"{v:.3f}") for v in m["joints"])
        click.echo(f"{m['motion']:<6} (line {m['line']}): {shown}{joints}")
    for o in trace.outputs:
        click.echo(f"output (line {o.line}): {o.name} = {'on' if o.value else 'off'} at {o.time:.3f} s")
    if trace.simulated:
        click.echo(f"simulated I/O (no device or declaration provides it): {', '.join(trace.simulated)}")
    for warning in trace.warnings:
        click.echo(f"warning: {warning}")
    if swept is not None:
        least, breach = swept
        if breach is not None:
            click.echo(f"CLEARANCE: {breach.text(check.clearance)}")
        elif least is not None:
            click.echo(f"clearance: least {least.distance:.1f} mm ({least.body} - {least.other}) at {least.where}, "
                       f"the {least.what}; the cell's clearance {check.clearance:g} mm")
    if failure is not None:
        click.echo(f"error: {failure}", err=True)
        click.echo(f"stopped by an error after {len(moves)} moves and {trace.steps} steps ({trace.clock:.3f} s)")
        sys.exit(1)
    if swept is not None and swept[1] is not None:
        sys.exit(1)
    if trace.halted:
        click.echo(f"HALT: {halt_text(trace)}")
    elif trace.ended is not None:
        click.echo(f"ended: {trace.ended}, after {len(moves)} moves and {trace.steps} steps ({trace.clock:.3f} s)")
    else:
        click.echo(f"ended after {trace.steps} steps")


def _cell_check(cell_path: str, target, filename: str, robot: str | None):
    """(the cell's arm for the target, the clearance check of the program's moves among the cell's solids)."""
    from codegen.cli_base import load
    from codegen.verify import clearance

    cell = load(cell_path)
    if robot is not None:
        raise UserError("--robot and --cell: the cell gives the arm ([cell.robot]); give one of them")
    if cell.robot is None or target.name not in cell.robot.arms:
        raise UserError(f"{cell_path}: the cell gives no arm for the {target.name} target ([cell.robot])")
    try:
        check = clearance.for_program(cell, target.name, filename)
    except ValueError as exc:
        raise UserError(f"{cell_path}: {exc}") from None
    if check is None:
        raise UserError(f"{cell_path}: the {target.name} arm has no link shapes to check (catalogue key `links`)")
    return cell.robot.arms[target.name], check


def _held(check, on: dict) -> bool:
    """A part in the gripper at the start: the cell's gripper feedback input given on (--signal)."""
    return check.feedback is not None and bool(on.get(check.feedback))


def _clearance_json(least, breach, clearance_mm: float) -> dict:
    def one(found):
        if found is None:
            return None
        return {"distance_mm": found.distance, "at_least_mm": found.lower_bound, "move": found.where,
                "what": found.what, "body": found.body, "other": found.other}

    return {"clearance_mm": clearance_mm, "least": one(least), "breach": one(breach)}
