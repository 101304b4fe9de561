"""`codegen run`: one program in the interpreter, with the simulated vision PC, gripper and arm."""

from __future__ import annotations

import math
import sys

import click

from codegen.cli_base import UserError, main, step_limit_option
from codegen.cli_base import dump as _dump
from codegen.controllers import all_targets, target_names


def _parse_input(text: str):
    name, sep, value = text.partition("=")
    if not sep or not name:
        raise UserError(f"--input: expected NAME=VALUE, got {text!r}")
    if "," in value:  # a record such as BASE_DATA[1]=X,Y,Z,A,B,C
        try:
            return name, tuple(float(v) for v in value.split(","))
        except ValueError:
            raise UserError(f"--input {name}: not numbers: {value!r}") from None
    try:
        return name, int(value)
    except ValueError:
        pass
    try:
        return name, float(value)
    except ValueError:
        raise UserError(f"--input {name}: not a number: {value!r}") from None


@main.command()
@click.argument("file", type=click.Path(exists=True, dir_okay=False))
@click.option(
    "--target",
    "target_name",
    type=click.Choice(target_names()),
    help="Controller (default: from the file suffix): "
    + "; ".join(f"{t.name} = {t.title}" for t in all_targets())
    + ".",
)
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
@step_limit_option("Stop a runaway program after this many steps.")
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def run(
    file: str,
    target_name: str | None,
    inputs: tuple[str, ...],
    signal_values: tuple[str, ...],
    gripper: str | None,
    start: str | None,
    robot: str | None,
    step_limit: int,
    as_json: bool,
) -> None:
    """Run one program in the built-in interpreter; print its log, moves (and joints) and halt."""
    from pathlib import Path

    from codegen.controllers import get_target
    from codegen.decimals import unsigned_zero
    from codegen.dialects import is_companion
    from codegen.dialects.core.values import RunError
    from codegen.poses import POSE_FORMATS
    from codegen.sim.gripper import Gripper
    from codegen.sim.vision_pc import VisionPC
    from codegen.verify.programs import load_file as load_program_file
    from codegen.verify.programs import target_of_file

    path = Path(file)
    if is_companion(path):
        raise UserError(f"{path}: a data file, read together with its program: run the program file")
    try:
        target = get_target(target_name or target_of_file(path))
    except ValueError as exc:
        raise UserError(str(exc)) from None
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
            joints = [float(v) for v in start.split(",")]
        except ValueError:
            joints = []
        if len(joints) != 6 or not all(math.isfinite(v) for v in joints):
            raise UserError(f"--start {start!r}: expected six joint angles J1,...,J6 in deg")
    on = {}
    for item in signal_values:
        name, sep, value = item.partition("=")
        if not sep or not name.strip() or value.strip() not in ("0", "1"):
            raise UserError(f"--signal {item!r}: expected NAME=0 or NAME=1")
        on[name.strip()] = value.strip() == "1"
    arm = None
    if robot is not None:
        from codegen.robot.arms import catalogue, find_arm

        arm = find_arm(robot)
        if arm is None:
            raise UserError(f"--robot {robot!r}: not in the catalogue; it has: {', '.join(catalogue())}")
        if arm.vendor != target.vendor:
            where = f"--robot {robot!r}"
            raise UserError(f"{where}: an arm of the {arm.vendor} controller; this program is for {target.name}")
    try:
        program = load_program_file(target, path)
    except RunError as exc:
        raise UserError(str(exc)) from None
    unknown = program.unknown_inputs(values)
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
        trace = program.run(values, step_limit=step_limit, devices=devices, arm=arm, signals=on, start_joints=joints)
    except RunError as exc:
        click.echo(f"error: {exc}", err=True)
        sys.exit(1)
    native = POSE_FORMATS[target.pose_format][2]
    moves = [
        {
            "motion": m.kind,
            "line": m.line,
            "pose": None if m.tcp2base is None else list(native(m.tcp2base)),
            "tcp2base": None if m.tcp2base is None else m.tcp2base.tolist(),
            "joints": None if m.joints is None else [round(float(v), 6) for v in m.joints],
        }
        for m in trace.moves
    ]
    if as_json:
        _dump(
            {
                "file": str(path),
                "target": target.name,
                "inputs": values,
                "messages": trace.messages,
                "moves": moves,
                "halted": trace.halted,
                "halt_message": trace.halt_message,
                "steps": trace.steps,
            }
        )
        return
    for message in trace.messages:
        click.echo(f"message: {message}")
    for m in moves:
        shown = "(a joint position)" if m["pose"] is None else " ".join(unsigned_zero(f"{v:.4f}") for v in m["pose"])
        joints = "" if m["joints"] is None else "  joints " + " ".join(unsigned_zero(f"{v:.3f}") for v in m["joints"])
        click.echo(f"{m['motion']:<6} (line {m['line']}): {shown}{joints}")
    if trace.halted:
        click.echo(f"HALT: {trace.halt_message}")
    else:
        click.echo(f"ended after {trace.steps} steps")
