"""KRL motion: PTP and LIN (Status, Turn, BCO, $BASE, $ROBROOT), path speed, approximation, $LOAD, numbered data."""

from __future__ import annotations

import re

from codegen.dialects import posemath
from codegen.dialects.core.machine import MoveEvent
from codegen.dialects.core.values import Record, RunError, f32
from codegen.dialects.krl.builtins import UNINIT, XYZABC, cart, cart_matrix, frame, new_value, valid, xyzabc
from codegen.poses import invert

AXES = ("AXIS", "E6AXIS")
# $BASE keeps its value from program to program (KSS 8 system variables): a program starts in whatever
# base was active. The interpreter assumes one that is not the robot's base, so a program that moves
# without setting $BASE ($NULLFRAME, or a BASE_DATA) moves somewhere else in its trace.
ACTIVE_BASE_AT_START = (250.0, -120.0, 40.0, 30.0, 0.0, 0.0)
# The controller's numbered data ($config.dat; KSS 8 system variables): type, count, how `--input` gives one
SYSTEM_ARRAYS = {
    "BASE_DATA": ("FRAME", 32, "X,Y,Z,A,B,C"),
    "TOOL_DATA": ("FRAME", 16, "X,Y,Z,A,B,C"),
    "LOAD_DATA": ("LOAD", 16, "M,X,Y,Z (kg, centre of gravity mm)"),
}
SYSTEM_ARRAY = re.compile(r"(BASE_DATA|TOOL_DATA|LOAD_DATA)\[(\d+)\]")


def load_record(values) -> Record:
    """A LOAD of mass m (kg) with its centre of gravity at x, y, z (mm) and no inertia (a point mass)."""
    m, x, y, z = (float(v) for v in values)
    inertia = Record("INERTIA", {"X": f32(0), "Y": f32(0), "Z": f32(0)})
    return Record("LOAD", {"M": f32(m), "CM": frame((x, y, z, 0, 0, 0)), "J": inertia})


def motion_rule(kind: str, pose: Record, arm, where: str) -> tuple:
    """How the controller picks the joints of a cartesian target (KSS 8 manual, Status and Turn): a PTP
    honours the target's S and T; a PTP without them keeps the current Status; LIN ignores S and T
    and keeps the configuration; a PTP with S but no T takes S and the shortest turn. The first motion
    (BCO) must be a PTP to a full position."""
    status = pose.type != "FRAME" and pose["S"] is not UNINIT
    status_turn = status and pose["T"] is not UNINIT
    if arm.arm is not None and not arm.known and not (kind == "joint" and status_turn):
        raise RunError(
            f"{where}: the first motion (BCO run) must be a PTP to a full position: an E6AXIS, or a POS or "
            "E6POS with S and T"
        )
    if kind == "joint" and status_turn:
        return "status_turn", (int(pose["S"]), int(pose["T"]))
    if kind == "joint" and status:  # S without T: the shortest turn from where the arm stands
        return "status", int(pose["S"])
    return ("keep",)


# The clock's TCP speed of a move (m/s): $VEL.CP where the program set it, else BAS(#INITMOV)'s
# default path speed, assumed 0.25 m/s here (the interpreter's clock only orders waits and photos).
DEFAULT_VEL_CP = 0.25


def tcp_speed(extra: dict) -> float:
    """The TCP speed of the next move in mm/s ($VEL.CP as the program set it)."""
    return extra.get("$VEL.CP", DEFAULT_VEL_CP) * 1000.0


def system_inputs(machine) -> dict | None:
    """Set the inputs that name the controller's numbered data (BASE_DATA[n], TOOL_DATA[n], LOAD_DATA[n])
    in machine.extra; the other inputs, or None when there are none of those."""
    if not any(SYSTEM_ARRAY.fullmatch(name.upper()) for name in machine.inputs):
        return None
    rest = {}
    for name, value in machine.inputs.items():
        match = SYSTEM_ARRAY.fullmatch(name.upper())
        if match is None:
            rest[name] = value
            continue
        array, index = match.group(1), int(match.group(2))
        type_name, size, shape = SYSTEM_ARRAYS[array]
        count = 6 if type_name == "FRAME" else 4
        if not 1 <= index <= size or not isinstance(value, tuple | list) or len(value) != count:
            raise RunError(f"input {name}: expected {array}[1..{size}] = {shape}")
        values = list(machine.extra.get(array) or [new_value(type_name) for _ in range(size)])
        values[index - 1] = frame(value) if type_name == "FRAME" else load_record(value)
        machine.extra[array] = values
    return rest


def robroot(machine) -> None:
    """`--input $ROBROOT=x,y,z,a,b,c`: the robot's base in the world ($ROBROOT, KSS 8 system variables;
    an arm on a track or a platform). Without it the interpreter takes the world at the robot's base."""
    for name, value in machine.inputs.items():
        if name.upper() == "$ROBROOT":
            if not isinstance(value, tuple | list) or len(value) != 6:
                raise RunError(f"input {name}: expected $ROBROOT = X,Y,Z,A,B,C")
            machine.extra["$ROBROOT"] = frame(value)


def world2robot(root: Record):
    """The world in the robot's base frame: the inverse of $ROBROOT as a 4x4 matrix."""
    return invert(cart_matrix(root))


# The path variables a program sets for its moves (KSS 8 system variables): $VEL.CP, the LIN path
# speed (m/s), and $APO.CDIS, the distance (mm) at which C_DIS approximation starts.
PATH_FIELDS = {("$VEL", "CP"), ("$APO", "CDIS")}


def path_variable_store(compiler, target_node, value_node, node):
    """`$VEL.CP = x` / `$APO.CDIS = x`: the statement that stores the number for the next moves, or
    None for any other assignment."""
    from lark import Tree

    if not (isinstance(target_node, Tree) and target_node.data == "field"):
        return None
    base, name = target_node.children
    if not (isinstance(base, Tree) and base.data == "var"):
        return None
    key = (str(base.children[0]).upper(), str(name).upper())
    if key not in PATH_FIELDS:
        return None
    value, where = compiler.expr(value_node), compiler.where(node)

    def store(fr):
        number = value(fr)
        if isinstance(number, bool | str | Record) or not float(number) > 0:
            raise RunError(f"{where}: {key[0]}.{key[1]} must be a positive number, got {number!r}")
        fr.m.extra[f"{key[0]}.{key[1]}"] = float(number)

    return store


def path_settings(static: dict, kind: str, extra: dict) -> dict:
    """What a PTP or LIN records: its approximation, the load, and for a LIN the path speed and for
    C_DIS the approximation distance the program set."""
    out = {**static, "load": load_of(extra.get("$LOAD")), "cdis": None}
    if static["approx"] == "C_DIS":
        out["cdis"] = extra.get("$APO.CDIS")
    if kind == "linear":
        out["vel_cp"] = extra.get("$VEL.CP")
    else:
        out["vel_ptp"] = extra.get("VEL_PTP")
    return out


def load_of(load) -> tuple | None:
    """$LOAD as (mass kg, centre of gravity x, y, z mm), or None before the program sets it."""
    if not isinstance(load, Record) or load["M"] is UNINIT:
        return None
    cm = load["CM"]
    return (float(load["M"]), *(float(cm[k]) if cm is not UNINIT else 0.0 for k in ("X", "Y", "Z")))


def motion_run(compiler, kind: str, static: dict, value, where: str, line: int):
    """A PTP or LIN at run time: its target as axis values (a joint target) or a cartesian pose in $BASE,
    recorded in the robot's base frame with the controller's configuration rule; the advance run goes on."""

    def run(fr):
        target = value(fr)
        if isinstance(target, Record) and target.type is None:  # a bare aggregate {X .., .., C ..}
            missing = [k for k, _ in XYZABC if k not in target]
            if missing:
                raise RunError(f"{where}: aggregate target lacks {', '.join(missing)} (no current pose here)")
            target = compiler.coerce("FRAME", target, where)
        settings = path_settings(static, kind, fr.m.extra)
        if isinstance(target, Record) and target.type in AXES:  # axis values: no solution to choose
            if kind != "joint":
                raise RunError(f"{where}: LIN takes a cartesian target")
            q = [float(valid(target[f"A{i}"], where, f"{target.type}.A{i}")) for i in range(1, 7)]
            event = MoveEvent(kind, None, line, settings)
            fr.m.arm.to_joints(event, q, where)
            fr.m.move(event, tcp_speed(fr.m.extra), runs_ahead=True)  # the advance run goes on
            return
        pose = cart(target, where)
        posemath.check_finite(xyzabc(pose), where, "motion target")
        base = fr.m.extra.get("$BASE") or frame(ACTIVE_BASE_AT_START)
        tcp2base = cart_matrix(pose)
        if base is not None and xyzabc(base) != (0, 0, 0, 0, 0, 0):  # $NULLFRAME: identity
            tcp2base = cart_matrix(base) @ tcp2base
        if "$ROBROOT" in fr.m.extra:  # $BASE is in the world; the trace is in the robot's base frame
            tcp2base = world2robot(fr.m.extra["$ROBROOT"]) @ tcp2base
        event = MoveEvent(kind, tcp2base, line, settings)
        fr.m.arm.to_pose(event, where, *motion_rule(kind, pose, fr.m.arm, where))
        fr.m.move(event, tcp_speed(fr.m.extra), runs_ahead=True)  # the advance run goes on

    return run
