"""RAPID data types (pose, robtarget...) and builtin functions (trig in degrees, Pose*, TPWrite, MoveJ/MoveL)."""

from __future__ import annotations

import math
import operator

import numpy as np

from codegen.dialects import posemath
from codegen.dialects.core.machine import MoveEvent, halt, pause
from codegen.dialects.core.values import F32, Record, RunError, f32, format_fixed
from codegen.dialects.rapid.messages import err_write

# Record types by field order (aggregates [a, b, ...] are positional).
RECORDS = {
    "POS": [("X", "NUM"), ("Y", "NUM"), ("Z", "NUM")],
    "ORIENT": [("Q1", "NUM"), ("Q2", "NUM"), ("Q3", "NUM"), ("Q4", "NUM")],
    "POSE": [("TRANS", "POS"), ("ROT", "ORIENT")],
    "CONFDATA": [("CF1", "NUM"), ("CF4", "NUM"), ("CF6", "NUM"), ("CFX", "NUM")],
    "EXTJOINT": [(f"EAX_{c}", "NUM") for c in "ABCDEF"],
    "ROBTARGET": [("TRANS", "POS"), ("ROT", "ORIENT"), ("ROBCONF", "CONFDATA"), ("EXTAX", "EXTJOINT")],
    "LOADDATA": [("MASS", "NUM"), ("COG", "POS"), ("AOM", "ORIENT"), ("IX", "NUM"), ("IY", "NUM"), ("IZ", "NUM")],
    "TOOLDATA": [("ROBHOLD", "BOOL"), ("TFRAME", "POSE"), ("TLOAD", "LOADDATA")],
    "ROBJOINT": [(f"RAX_{i}", "NUM") for i in range(1, 7)],  # rax_1..rax_6 (RAPID data types, robjoint)
    "JOINTTARGET": [("ROBAX", "ROBJOINT"), ("EXTAX", "EXTJOINT")],
    "WOBJDATA": [("ROBHOLD", "BOOL"), ("UFPROG", "BOOL"), ("UFMEC", "STRING"), ("UFRAME", "POSE"), ("OFRAME", "POSE")],
    "SPEEDDATA": [("V_TCP", "NUM"), ("V_ORI", "NUM"), ("V_LEAX", "NUM"), ("V_REAX", "NUM")],
    "ZONEDATA": [
        ("FINEP", "BOOL"),
        *((k, "NUM") for k in ("PZONE_TCP", "PZONE_ORI", "PZONE_EAX", "ZONE_ORI", "ZONE_LEAX", "ZONE_REAX")),
    ],
}
SCALARS = {"NUM", "DNUM", "BOOL", "STRING"}

STRING_MAX = 80  # characters of a RAPID string (RAPID kernel manual, string; targets/abb.toml string_max)

# Move timing (ABB, "Technical reference manual - RAPID Instructions, Functions and Data types", speeddata
# and zonedata, as recalled; the manual's text was not found during this work):
# - speeddata [v_tcp mm/s, v_ori deg/s, v_leax mm/s, v_reax deg/s]; the predefined vN have v_tcp = N
#   mm/s (v5 ... v7000); vmax: the robot type's maximum TCP speed, 5000 mm/s in the manual's table
#   (uncertain: later manuals give it as the robot's own maximum, MaxRobSpeed); a move's \V:=n replaces v_tcp;
# - zonedata [finep, pzone_tcp, ...]: finep TRUE is a stop point (the move ends before the next
#   instruction runs, as the predefined fine); FALSE a fly-by point (z0 ... z200): program execution
#   runs ahead while the arm moves.


def _zero(type_name: str):
    if type_name in RECORDS:
        return Record(type_name, {k: _zero(t) for k, t in RECORDS[type_name]})
    return {"NUM": f32(0), "DNUM": 0.0, "BOOL": False, "STRING": ""}.get(type_name, f32(0))


_ZEROS = {name: _zero(name) for name in [*RECORDS, *SCALARS]}


def zero(type_name: str):
    """The value RAPID gives a declared variable without an initial value."""
    return _ZEROS.get(type_name, _ZEROS["NUM"])  # shared: values are never changed in place


def type_text(value) -> str:
    """A value's RAPID data type, for messages."""
    if isinstance(value, Record):
        return str(value.type).lower()
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, str):
        return "string"
    if isinstance(value, list):
        return "array"
    if isinstance(value, int | float | np.number):
        return "num"
    return type(value).__name__


def num(value, where: str) -> float:
    if type(value) is F32:  # the common case first
        return float(value)
    if isinstance(value, bool) or not isinstance(value, int | float | np.number):
        raise RunError(f"{where}: expected a num, got {type_text(value)}")
    return float(value)


def rec(value, type_name: str, where: str) -> Record:
    if not isinstance(value, Record) or value.type != type_name:
        raise RunError(f"{where}: expected {type_name.lower()}, got {type_text(value)}")
    return value


def vec(rec: Record, keys) -> list[float]:
    if keys == "XYZ":
        return list(map(float, _xyz(rec)))
    if keys == QUAT_KEYS:
        return list(map(float, _quat(rec)))
    return [float(rec[k]) for k in keys]


QUAT_KEYS = ("Q1", "Q2", "Q3", "Q4")
_xyz = operator.itemgetter("X", "Y", "Z")  # a pos record's numbers
_quat = operator.itemgetter(*QUAT_KEYS)  # an orient record's numbers


def pose_record(trans, quat) -> Record:
    x, y, z = trans
    q1, q2, q3, q4 = quat
    return Record(
        "POSE",
        {
            "TRANS": Record("POS", {"X": f32(x), "Y": f32(y), "Z": f32(z)}),
            "ROT": Record("ORIENT", {"Q1": f32(q1), "Q2": f32(q2), "Q3": f32(q3), "Q4": f32(q4)}),
        },
    )


def builtins(compiler) -> dict:
    """The RAPID functions and procedures the interpreter provides, by upper-case name; compiler
    supplies the coercions of record aggregates."""
    from codegen.dialects.rapid.motion import (  # the motion helpers build on this module's types
        check_circle,
        conf_now,
        move_event,
        move_load,
        move_setting,
        move_timing,
        no_motion_in_trap,
        robtarget_from,
        target_pose,
        tcp_now,
        tool_matrix,
        wobj_matrix,
    )

    def trig(fn):
        return lambda fr, a, k, w: f32(fn(math.radians(num(a[0], w))))

    def atan2(fr, args, kwargs, where):
        return f32(math.degrees(math.atan2(num(args[0], where), num(args[1], where))))

    def sqrt(fr, args, kwargs, where):
        value = num(args[0], where)
        if value < 0:
            raise RunError(f"{where}: Sqrt of a negative number")
        return f32(math.sqrt(value))

    def abs_(fr, args, kwargs, where):
        return f32(abs(num(args[0], where)))

    def orient_zyx(fr, args, kwargs, where):
        z, y, x = (num(a, where) for a in args)
        return Record(
            "ORIENT",
            dict(zip(("Q1", "Q2", "Q3", "Q4"), (f32(v) for v in posemath.quat_from_zyx_deg(z, y, x)), strict=True)),
        )

    def euler_zyx(fr, args, kwargs, where):
        axis = next((k for k in kwargs if k in ("X", "Y", "Z")), None)
        if axis is None or len(args) != 1:
            raise RunError(f"{where}: EulerZYX needs one of \\X, \\Y, \\Z and an orient")
        q = vec(rec(args[0], "ORIENT", where), ("Q1", "Q2", "Q3", "Q4"))
        m = posemath.matrix_from_abb((0, 0, 0, *q))
        a, b, c = posemath.xyzabc_from_matrix(m)[3:]
        return f32({"Z": a, "Y": b, "X": c}[axis])

    def norient(fr, args, kwargs, where):
        q1, q2, q3, q4 = vec(rec(args[0], "ORIENT", where), ("Q1", "Q2", "Q3", "Q4"))
        n = math.sqrt(q1 * q1 + q2 * q2 + q3 * q3 + q4 * q4)
        if n == 0 or not math.isfinite(n):
            raise RunError(f"{where}: NOrient of a zero or non-finite orientation")
        return Record("ORIENT", {"Q1": f32(q1 / n), "Q2": f32(q2 / n), "Q3": f32(q3 / n), "Q4": f32(q4 / n)})

    def pose_parts(value, where):
        """Position and quaternion of a pose, or of an aggregate [pos, orient]."""
        if type(value) is list and len(value) == 2 and all(type(v) is Record for v in value):
            trans, rot = value
            if trans.type != "POS" or rot.type != "ORIENT":
                trans, rot = compiler.coerce("POSE", value, where).values()
        else:
            trans, rot = compiler.coerce("POSE", value, where).values()
        return (
            [float(trans["X"]), float(trans["Y"]), float(trans["Z"])],
            [float(rot["Q1"]), float(rot["Q2"]), float(rot["Q3"]), float(rot["Q4"])],
        )

    def pose_mult(fr, args, kwargs, where):
        (t1, q1), (t2, q2) = (pose_parts(a, where) for a in args)
        rotated = posemath.quat_rotate(q1, t2)
        trans = [a + b for a, b in zip(t1, rotated, strict=True)]
        return pose_record(trans, posemath.quat_multiply(q1, q2))

    def pose_inv(fr, args, kwargs, where):
        t, q = pose_parts(args[0], where)
        conj = (q[0], -q[1], -q[2], -q[3])
        trans = [-v for v in posemath.quat_rotate(conj, t)]
        return pose_record(trans, conj)

    def pose_vect(fr, args, kwargs, where):
        t, q = pose_parts(args[0], where)
        p = vec(compiler.coerce("POS", args[1], where), "XYZ")
        out = [a + b for a, b in zip(t, posemath.quat_rotate(q, p), strict=True)]
        return Record("POS", dict(zip("XYZ", (f32(v) for v in out), strict=True)))

    def offs(fr, args, kwargs, where):
        """Offs(Point, XOffset, YOffset, ZOffset): the robtarget moved by the offsets (mm) in its object
        frame, the one its move's work object gives it; orientation, robconf and external axes unchanged
        (RAPID functions, Offs)."""
        if len(args) != 4 or kwargs:
            raise RunError(f"{where}: Offs takes a robtarget and three offsets (mm)")
        point = args[0]
        if type(point) is not Record or point.type != "ROBTARGET":
            point = compiler.coerce("ROBTARGET", point, where)
        dx, dy, dz = (num(a, where) for a in args[1:])
        trans = point["TRANS"]
        moved = point.shallow()
        moved["TRANS"] = Record("POS", {k: f32(trans[k] + d) for k, d in zip("XYZ", (dx, dy, dz), strict=True)})
        return moved

    def num_to_str(fr, args, kwargs, where):
        decimals = int(num(args[1], where))
        if not 0 <= decimals <= STRING_MAX:
            raise RunError(f"{where}: NumToStr decimals {decimals}: a string holds at most {STRING_MAX} characters")
        text = format_fixed(num(args[0], where), decimals)
        if len(text) > STRING_MAX:
            raise RunError(f"{where}: NumToStr result longer than {STRING_MAX} characters")
        return text

    def tpwrite(fr, args, kwargs, where):
        text = args[0]
        if not isinstance(text, str):
            raise RunError(f"{where}: TPWrite needs a string")
        if "NUM" in kwargs:
            text += num_text(kwargs["NUM"])
        if len(text) > STRING_MAX:
            raise RunError(f"{where}: TPWrite text longer than {STRING_MAX} characters")
        fr.m.message(text)

    def move(kind):
        def run(fr, args, kwargs, where):
            no_motion_in_trap(fr, where, "MoveJ" if kind == "joint" else "MoveL")
            timing = move_timing(args, kwargs, where)
            m, target = target_pose(compiler, args[0], kwargs.get("WOBJ"), where)
            event = move_event(fr, kind, m, target, args, timing, where)
            fr.m.move(event, *timing)

        return run

    def move_c(fr, args, kwargs, where):
        """MoveC CirPoint, ToPoint, Speed, Zone, Tool [\\WObj] [\\V]: the TCP on the circle through where the
        previous motion ends, CirPoint and ToPoint; it takes the arc's length over the speed's v_tcp. The
        orientation is the start's along the arc (the interpreter's circular path) and ToPoint's at its end;
        the arm's joints are solved at ToPoint only (not along the arc)."""
        no_motion_in_trap(fr, where, "MoveC")
        if len(args) != 5:
            given = f"{len(args)} arguments given"
            raise RunError(f"{where}: MoveC takes CirPoint, ToPoint, Speed, Zone and Tool ({given})")
        unknown = sorted(set(kwargs) - {"WOBJ", "V"})
        if unknown:
            raise RunError(f"{where}: MoveC \\{unknown[0].title()} is not supported here")
        rest = args[1:]  # ToPoint, Speed, Zone, Tool: as MoveL's arguments
        timing = move_timing(rest, kwargs, where)
        via, _cir = target_pose(compiler, args[0], kwargs.get("WOBJ"), where)
        m, target = target_pose(compiler, args[1], kwargs.get("WOBJ"), where)
        last = fr.m.last_move
        check_circle(None if last is None else last.tcp2base, via, m, where)
        event = move_event(fr, "linear", m, target, rest, timing, where)
        event.settings["circle_point"] = [float(v) for v in via[:3, 3]]
        fr.m.move(event, *timing, via=via)

    def c_rob_t(fr, args, kwargs, where):
        """CRobT(\\Tool:=tool \\WObj:=wobj): the robtarget where the arm is now (where the clock finds it on
        the path of a move under way: in a TRAP, the cycle its interrupt came), for that tool in that work
        object. Without \\Tool or \\WObj the controller takes the active ones (assumed, as recalled: RAPID
        functions, CRobT), which the interpreter does not keep: both are required here."""
        if args or set(kwargs) != {"TOOL", "WOBJ"}:
            raise RunError(f"{where}: CRobT takes \\Tool:= and \\WObj:= here (the active ones are not tracked)")
        tool2flange = tool_matrix(kwargs["TOOL"], where)
        base2wobj = np.linalg.inv(wobj_matrix(compiler, kwargs["WOBJ"], where))
        tcp2base, active = tcp_now(fr.m)
        if tcp2base is None:
            raise RunError(f"{where}: CRobT: the arm's pose is not known here (no move to a pose yet)")
        pose = base2wobj @ tcp2base @ np.linalg.inv(active) @ tool2flange
        return robtarget_from(pose, conf_now(fr.m), where)

    def configuration_check(name):
        def run(fr, args, kwargs, where):
            # ConfJ \On / \Off, ConfL \On / \Off: the configuration check of MoveJ / MoveL (on by default)
            switches = set(kwargs)
            if len(switches & {"ON", "OFF"}) != 1 or args:
                raise RunError(f"{where}: {name} takes \\On or \\Off")
            fr.m.extra[name] = "ON" in switches

        return run

    def c_joint_t(fr, args, kwargs, where):
        """CJointT(): the arm's current joint angles (deg) as a jointtarget (RAPID functions)."""
        q = fr.m.arm.actual(where)
        return compiler.coerce("JOINTTARGET", [[f32(v) for v in q], [f32(9e9)] * 6], where)

    def move_abs_j(fr, args, kwargs, where):
        no_motion_in_trap(fr, where, "MoveAbsJ")
        target = args[0]
        if type(target) is not Record or target.type != "JOINTTARGET":
            target = compiler.coerce("JOINTTARGET", target, where)
        q = vec(target["ROBAX"], tuple(f"RAX_{i}" for i in range(1, 7)))
        posemath.check_finite(q, where, "joint target")
        speed, zone, tool = (move_setting(args, i) for i in (1, 2, 3))
        settings = {"speed": speed, "zone": zone, "tool": tool, "load": move_load(fr, args, where)}
        event = MoveEvent("joint", None, int(where.split(":")[1]), settings)
        fr.m.arm.to_joints(event, q, where)
        fr.m.move(event, *move_timing(args, kwargs, where))

    return {
        "SIN": trig(math.sin),
        "COS": trig(math.cos),
        "TAN": trig(math.tan),
        "ATAN2": atan2,
        "SQRT": sqrt,
        "ABS": abs_,
        "ORIENTZYX": orient_zyx,
        "EULERZYX": euler_zyx,
        "NORIENT": norient,
        "POSEMULT": pose_mult,
        "POSEINV": pose_inv,
        "POSEVECT": pose_vect,
        "OFFS": offs,
        "NUMTOSTR": num_to_str,
        "TPWRITE": tpwrite,
        "ERRWRITE": err_write,
        "STOP": pause,  # the program resumes at the next instruction when the operator presses start
        "EXIT": halt,
        "MOVEJ": move("joint"),
        "MOVEL": move("linear"),
        "MOVEABSJ": move_abs_j,
        "MOVEC": move_c,
        "CROBT": c_rob_t,
        "CJOINTT": c_joint_t,
        "CONFJ": configuration_check("CONFJ"),
        "CONFL": configuration_check("CONFL"),
    }


def num_text(value) -> str:
    """TPWrite \\Num: integers without decimals, else up to 6 significant digits (as the FlexPendant)."""
    v = float(value)
    if v == int(v) and abs(v) < 1e9:
        return str(int(v))
    return f"{v:.6g}"
