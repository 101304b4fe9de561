"""KRL motion: PTP, LIN, CIRC (Status, Turn, BCO, $BASE, $ROBROOT), path speed, approximation, $LOAD, numbered data."""

from __future__ import annotations

import re

import numpy as np

from codegen.dialects import posemath
from codegen.dialects.core.machine import MoveEvent
from codegen.dialects.core.values import Record, RunError, f32
from codegen.dialects.krl import trigger
from codegen.dialects.krl.builtins import UNINIT, XYZABC, cart, cart_matrix, frame, shown, valid, xyzabc
from codegen.dialects.krl.numbered import SYSTEM_ARRAYS, fresh_values
from codegen.dialects.krl.position import base2robot, record_base
from codegen.dialects.krl.sysvars import axis_act
from codegen.poses import rotmat_from_zyx_deg
from codegen.world import loads

AXES = ("AXIS", "E6AXIS")
# The controller's numbered data ($config.dat; KSS 8 system variables): type, count, how `--input` gives one
SYSTEM_ARRAY = re.compile(r"(BASE_DATA|TOOL_DATA|LOAD_DATA)\[(\d+)\]")


def load_record(values) -> Record:
    """A LOAD of mass m (kg) with its centre of gravity at x, y, z (mm), its principal axes turned a, b, c (deg)
    and its moments jx, jy, jz (kg m2) about them; given m, x, y, z alone: a point mass."""
    m, x, y, z, a, b, c, jx, jy, jz = (*(float(v) for v in values), *(0.0,) * (10 - len(values)))
    inertia = Record("INERTIA", {"X": f32(jx), "Y": f32(jy), "Z": f32(jz)})
    return Record("LOAD", {"M": f32(m), "CM": frame((x, y, z, a, b, c)), "J": inertia})


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


def tcp_speed(sysvars: dict) -> float:
    """The TCP speed of the next move in mm/s ($VEL.CP as the program set it)."""
    return sysvars.get("$VEL.CP", DEFAULT_VEL_CP) * 1000.0


def tcp_accel(sysvars: dict) -> float | None:
    """A LIN's path acceleration in mm/s2: $ACC.CP (m/s2: KSS 8 System Variables, $ACC) as the program or
    BAS(#INITMOV) set it (DEF_ACC_CP), None while nothing set it (the clock then counts no ramp)."""
    acc = sysvars.get("$ACC.CP")
    return None if acc is None else acc * 1000.0


def system_inputs(machine) -> dict | None:
    """Set the inputs that name the controller's numbered data (BASE_DATA[n], TOOL_DATA[n], LOAD_DATA[n])
    in machine.state.sysvars; the other inputs, or None when there are none of those."""
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
        counts = (6,) if type_name == "FRAME" else (4, 10)
        if not 1 <= index <= size or not isinstance(value, tuple | list) or len(value) not in counts:
            raise RunError(f"input {name}: expected {array}[1..{size}] = {shape}")
        values = list(fresh_values(machine, array))
        values[index - 1] = frame(value) if type_name == "FRAME" else load_record(value)
        machine.state.sysvars[array] = values
    return rest


def robroot(machine) -> None:
    """`--input $ROBROOT=x,y,z,a,b,c`: the robot's base in the world ($ROBROOT, KSS 8 system variables;
    an arm on a track or a platform). Without it the interpreter takes the world at the robot's base."""
    for name, value in machine.inputs.items():
        if name.upper() == "$ROBROOT":
            if not isinstance(value, tuple | list) or len(value) != 6:
                raise RunError(f"input {name}: expected $ROBROOT = X,Y,Z,A,B,C")
            machine.state.sysvars["$ROBROOT"] = frame(value)


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
            raise RunError(f"{where}: {key[0]}.{key[1]} must be a positive number, got {shown(number)}")
        fr.m.state.sysvars[f"{key[0]}.{key[1]}"] = float(number)

    return store


def path_settings(static: dict, kind: str, sysvars: dict) -> dict:
    """What a PTP or LIN records (MoveEvent.settings): "approx" (C_PTP, C_DIS, C_VEL, C_ORI, C_SPL or None),
    "load" (load_of), "cdis" ($APO.CDIS mm, for C_DIS), for a LIN "vel_cp" ($VEL.CP m/s) and "acc_cp" ($ACC.CP
    m/s2), for a PTP "vel_ptp" and "acc_ptp" ($VEL_AXIS[1] / $ACC_AXIS[1] %: BAS(#VEL_PTP ...)), and "ov_pro"
    ($OV_PRO %); None: the program (or BAS) did not set it."""
    out = {**static, "load": load_of(sysvars.get("$LOAD")), "cdis": None, "ov_pro": sysvars.get("$OV_PRO")}
    if static["approx"] == "C_DIS":
        out["cdis"] = sysvars.get("$APO.CDIS")
    if kind == "linear":
        out["vel_cp"] = sysvars.get("$VEL.CP")
        out["acc_cp"] = sysvars.get("$ACC.CP")
    else:
        out["vel_ptp"] = sysvars.get("VEL_PTP")
        out["acc_ptp"] = sysvars.get("ACC_PTP")
    return out


def load_of(load) -> tuple | None:
    """$LOAD as verify compares a load (codegen.world.loads.Load.flat: mass kg, centre of gravity mm, the tensor at
    it in flange axes kg m2), or None before the program sets it. M, CM {X, Y, Z, A, B, C}: the centre of mass and
    the principal axes' orientation relative to the flange, J {X, Y, Z}: the moments about them (targets/kuka.toml
    cites the form); a part not set counts 0."""
    last = _LAST_LOAD
    if load is last[0]:  # the same record as the last move's (records never change in place): the same load
        return last[1]
    if not isinstance(load, Record) or load["M"] is UNINIT:
        return None
    cm, j = load["CM"], load["J"]
    flat = _flat_load(float(load["M"]), *(_set(cm, k) for k, _ in XYZABC), *(_set(j, k) for k in ("X", "Y", "Z")))
    _remember_load(load, flat)
    return flat


_LAST_LOAD: tuple = (object(), None)  # (the $LOAD record, its load_of), held so that its identity stays its own


def _remember_load(load: Record, flat: tuple) -> None:
    global _LAST_LOAD
    _LAST_LOAD = (load, flat)


@loads.Remembered
def _flat_load(mass: float, x: float, y: float, z: float, a: float, b: float, c: float, *moments: float) -> tuple:
    return loads.from_principal(mass, (x, y, z), rotmat_from_zyx_deg(a, b, c), list(moments)).flat()


def _set(record, key: str) -> float:
    """A component of a record the program may have left (partly) without value: 0 then."""
    if record is UNINIT or record.get(key, UNINIT) is UNINIT:
        return 0.0
    return float(record[key])


def whole_frame(compiler, target, where: str, lacks: str, fr=None):
    """A bare aggregate {X .., .., C ..} as a FRAME, refused when it lacks a component (no current pose here
    to fill it from; lacks: the message, {} the missing names); a bare {A1 .., ..} as an E6AXIS (the axes it
    does not name stay where they are, where the interpreter knows that); any other value as it is."""
    bare = isinstance(target, Record) and target.type is None
    if bare and any(k.startswith("A") and k[1:].isdigit() for k in target):
        return axis_aggregate(compiler, target, where, fr)
    if isinstance(target, Record) and target.type is None:
        missing = [k for k, _ in XYZABC if k not in target]
        if missing:
            raise RunError(f"{where}: " + lacks.format(", ".join(missing)))
        kind = "POS" if "S" in target or "T" in target else "FRAME"
        kind = "E6POS" if any(k.startswith("E") for k in target) else kind
        target = compiler.coerce(kind, target, where)
    return target


def axis_aggregate(compiler, target: Record, where: str, fr) -> Record:
    """{A1 .., A2 .., ...} as the motion's E6AXIS: every axis named, or the others from where they stand."""
    names = [f"A{i}" for i in range(1, 7)]
    missing = [k for k in names if k not in target]
    values = dict(target)
    if missing:
        try:
            now = axis_act(fr, where)
        except RunError:
            raise RunError(
                f"{where}: the axis target lacks {', '.join(missing)} and where those axes stand is not known here"
            ) from None
        values = {**{k: now[k] for k in missing}, **values}
    return compiler.coerce("E6AXIS", Record(None, values), where)


def motion_run(compiler, kind: str, static: dict, value, where: str, line: int):
    """A PTP or LIN at run time: its target as axis values (a joint target) or a cartesian pose in $BASE,
    recorded in the robot's base frame with the controller's configuration rule; the advance run goes on."""

    def run(fr):
        target = whole_frame(compiler, value(fr), where, "aggregate target lacks {} (no current pose here)", fr)
        sysvars = fr.m.state.sysvars
        settings = path_settings(static, kind, sysvars)
        if "$IPO_MODE" in sysvars and sysvars["$IPO_MODE"] != "#BASE":
            raise RunError(f"{where}: $IPO_MODE {sysvars['$IPO_MODE']} (an external TCP) is not modelled")
        if isinstance(target, Record) and target.type in AXES:  # axis values: no solution to choose
            if kind != "joint":
                raise RunError(f"{where}: LIN takes a cartesian target")
            q = [float(valid(target[f"A{i}"], where, f"{target.type}.A{i}")) for i in range(1, 7)]
            event = MoveEvent(kind, None, line, settings)
            fr.m.arm.to_joints(event, q, where)
            commanded(fr.m, event, tcp_speed(sysvars))
            return
        pose = cart(target, where)
        posemath.check_finite(xyzabc(pose), where, "motion target")
        base = base2robot(fr.m.state.sysvars)
        tcp2base = base @ cart_matrix(pose)
        if kind == "linear" and fr.m.state.sysvars.get("$ORI_TYPE") == "#CONSTANT":
            tcp2base[:3, :3] = start_orientation(fr, "LIN", where)
        event = MoveEvent(kind, tcp2base, line, settings)
        fr.m.arm.to_pose(event, where, *motion_rule(kind, pose, fr.m.arm, where))
        record_base(fr.m, event, base)
        commanded(fr.m, event, tcp_speed(sysvars), accel=tcp_accel(sysvars) if kind == "linear" else None)

    return run


def commanded(m, event: MoveEvent, speed: float, via=None, accel: float | None = None) -> None:
    """The move recorded: the advance run goes on (unless $ADVANCE is 0: then the program waits for each
    motion); the tool it was planned with kept ($POS_ACT), the TRIGGERs on it switched. accel: a LIN's path
    acceleration (mm/s2): its time a trapezoid from standstill to standstill (an approximated LIN's blend,
    which does not stop, is not modelled: its time is the longer one)."""
    sysvars = m.state.sysvars
    triggers = bool(m.state.triggers)
    t0 = max(m.clock, m.arm_until) if triggers else 0.0
    m.move(event, speed, runs_ahead=sysvars.get("$ADVANCE") != 0, via=via, accel_mm_s2=accel)
    m.state.tool_at_move = m.arm.tcp2flange
    if triggers:
        trigger.fire(m, event, t0, speed)


# $ORI_TYPE and $CIRC_TYPE (KSS 8 system variables, recalled, not confirmed from the manual here):
# $ORI_TYPE #CONSTANT keeps the start's orientation over a LIN or CIRC (the end point's orientation is
# disregarded), #VAR and #JOINT change it to the end's; $CIRC_TYPE #BASE holds a CIRC's orientation
# in the base, #PATH turns it with the path's tangent. The interpreter runs CIRC with #CONSTANT and #BASE
# only (the core's circular path holds the start's orientation), and assumes no default for either.
ORI_TYPES = frozenset({"#CONSTANT", "#VAR", "#JOINT"})
CIRC_TYPES = frozenset({"#BASE", "#PATH"})
ORIENTATION_VARIABLES = {"$ORI_TYPE": ORI_TYPES, "$CIRC_TYPE": CIRC_TYPES}


def orientation_store(compiler, target_node, value_node, node):
    """`$ORI_TYPE = #CONSTANT` / `$CIRC_TYPE = #BASE`: the statement that keeps it for the next moves, or
    None for any other assignment."""
    from lark import Tree

    if not (isinstance(target_node, Tree) and target_node.data == "var"):
        return None
    key = str(target_node.children[0]).upper()
    if key not in ORIENTATION_VARIABLES:
        return None
    value, where, allowed = compiler.expr(value_node), compiler.where(node), ORIENTATION_VARIABLES[key]

    def store(fr):
        v = value(fr)
        if not isinstance(v, str) or v.upper() not in allowed:
            raise RunError(f"{where}: {key} takes {', '.join(sorted(allowed))}, got {shown(v)}")
        fr.m.state.sysvars[key] = v.upper()

    return store


def start_orientation(fr, what: str, where: str) -> np.ndarray:
    """The orientation (3x3, robot's base frame) the arm has where the move starts: the last move's end."""
    last = fr.m.last_move
    if last is not None and last.tcp2base is None:
        fr.m.arm.resolve()  # a PTP to axis values: its pose from the arm's kinematics, where known
    if last is None or last.tcp2base is None:
        raise RunError(
            f"{where}: {what} with $ORI_TYPE = #CONSTANT: the orientation where it starts is not known here "
            "(the first motion, or a PTP to axis values without the arm's model)"
        )
    return last.tcp2base[:3, :3].copy()


def circ_run(compiler, static: dict, aux_value, end_value, where: str, line: int):
    """CIRC aux, end: the circle from where the arm is through aux to end (both in $BASE), at $VEL.CP (its
    time the arc's length over it); the orientation the start's ($ORI_TYPE #CONSTANT, $CIRC_TYPE #BASE);
    the advance run goes on. The aux point's orientation is disregarded (KSS 8 manual, recalled)."""
    from codegen.dialects.core.watch import Path

    def target(fr, value, what: str) -> tuple[Record, np.ndarray]:
        pose = whole_frame(compiler, value(fr), where, f"CIRC {what} lacks {{}}")
        if isinstance(pose, Record) and pose.type in AXES:
            raise RunError(f"{where}: CIRC takes cartesian points (FRAME, POS, E6POS), its {what} is {pose.type}")
        pose = cart(pose, where)
        posemath.check_finite(xyzabc(pose), where, f"CIRC {what}")
        return pose, base2robot(fr.m.state.sysvars) @ cart_matrix(pose)

    def run(fr):
        sysvars = fr.m.state.sysvars
        if sysvars.get("$ORI_TYPE") != "#CONSTANT":
            raise RunError(
                f"{where}: CIRC with $ORI_TYPE {sysvars.get('$ORI_TYPE', 'not set')}: the interpreter models CIRC "
                "with $ORI_TYPE = #CONSTANT (the start's orientation held): set it before the CIRC"
            )
        if sysvars.get("$CIRC_TYPE") != "#BASE":
            raise RunError(
                f"{where}: CIRC with $CIRC_TYPE {sysvars.get('$CIRC_TYPE', 'not set')}: the interpreter models CIRC "
                "with $CIRC_TYPE = #BASE (the orientation held in the base): set it before the CIRC"
            )
        last = fr.m.last_move
        if last is None or last.tcp2base is None:
            raise RunError(
                f"{where}: CIRC: where the circle starts is not known here (the first motion, or a PTP to axis "
                "values before it): move to a cartesian pose first"
            )
        _aux, aux = target(fr, aux_value, "auxiliary point")
        end_pose, end = target(fr, end_value, "end point")
        start = last.tcp2base
        aux[:3, :3] = end[:3, :3] = start[:3, :3]
        try:
            Path(start, end, aux)
        except RunError as exc:
            raise RunError(f"{where}: CIRC: {exc}") from None
        for p, what in ((aux, "auxiliary point"), (end, "end point")):
            if np.linalg.norm(p[:3, 3] - start[:3, 3]) < CIRC_MIN_MM:
                raise RunError(f"{where}: CIRC: the {what} is where the circle starts")
        if np.linalg.norm(aux[:3, 3] - end[:3, 3]) < CIRC_MIN_MM:
            raise RunError(f"{where}: CIRC: the auxiliary point is the end point")
        settings = {**path_settings(static, "linear", sysvars), "circ": True}
        event = MoveEvent("linear", end, line, settings)
        fr.m.arm.to_pose(event, where, *motion_rule("linear", end_pose, fr.m.arm, where))
        record_base(fr.m, event, base2robot(sysvars))
        commanded(fr.m, event, tcp_speed(sysvars), via=aux)

    return run


CIRC_MIN_MM = 0.1  # assumed: how close a CIRC's points may lie (the controller refuses coincident points)


class CircStatement:
    """Compiler mixin: CIRC aux, end (without CA: a circular angle is not modelled)."""

    def s_circ_stmt(self, node):
        _keyword, aux, end, angle_name, _angle, approx = node.children
        if angle_name is not None:
            if str(angle_name).upper() != "CA":
                self.fail(angle_name, f"CIRC aux, end, {angle_name}: expected CA (the circular angle)")
            self.fail(angle_name, "CIRC with CA (a circular angle) is not modelled by this interpreter")
        static = {"approx": str(approx).upper() if approx is not None else None}
        return circ_run(self, static, self.expr(aux), self.expr(end), self.where(node), self.line(node))
