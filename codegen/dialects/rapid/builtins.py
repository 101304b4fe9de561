"""RAPID built-in routines: pose math (Pose*, Offs, OrientZYX), TPWrite, stops, MoveJ/MoveL/MoveC/MoveAbsJ, CRobT."""

from __future__ import annotations

import math

import numpy as np

from codegen.dialects import posemath
from codegen.dialects.core.machine import MoveEvent, halt, pause
from codegen.dialects.core.values import Record, RunError, f32
from codegen.dialects.rapid import motionset, tracking
from codegen.dialects.rapid.messages import err_write, ui_message_box
from codegen.dialects.rapid.modules import save
from codegen.dialects.rapid.motion import (
    check_circle,
    conf_now,
    make_active,
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
    zone_radius,
)
from codegen.dialects.rapid.predefined import VMAX_TCP
from codegen.dialects.rapid.types import QUAT_KEYS, num, orient_record, pos_record, pose_record, rec, vec


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


def pose_parts(compiler, value, where):
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
    (t1, q1), (t2, q2) = (pose_parts(fr.m.program.compiler, a, where) for a in args)
    rotated = posemath.quat_rotate(q1, t2)
    trans = [a + b for a, b in zip(t1, rotated, strict=True)]
    return pose_record(trans, posemath.quat_multiply(q1, q2))


def pose_inv(fr, args, kwargs, where):
    t, q = pose_parts(fr.m.program.compiler, args[0], where)
    conj = (q[0], -q[1], -q[2], -q[3])
    trans = [-v for v in posemath.quat_rotate(conj, t)]
    return pose_record(trans, conj)


def pose_vect(fr, args, kwargs, where):
    compiler = fr.m.program.compiler
    t, q = pose_parts(fr.m.program.compiler, args[0], where)
    p = vec(compiler.coerce("POS", args[1], where), "XYZ")
    out = [a + b for a, b in zip(t, posemath.quat_rotate(q, p), strict=True)]
    return Record("POS", dict(zip("XYZ", (f32(v) for v in out), strict=True)))


def offs(fr, args, kwargs, where):
    """Offs(Point, XOffset, YOffset, ZOffset): the robtarget moved by the offsets (mm) in its object
    frame, the one its move's work object gives it; orientation, robconf and external axes unchanged
    (RAPID functions, Offs)."""
    compiler = fr.m.program.compiler
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


def rel_tool(fr, args, kwargs, where):
    """RelTool(Point, Dx, Dy, Dz [\\Rx] [\\Ry] [\\Rz]): the robtarget displaced in its own (the tool's) frame:
    by (Dx, Dy, Dz) mm, and turned about its x axis, then the new y, then the new z (deg); robconf and
    external axes unchanged (RAPID functions, RelTool, as recalled)."""
    compiler = fr.m.program.compiler
    if len(args) != 4 or set(kwargs) - {"RX", "RY", "RZ"}:
        raise RunError(f"{where}: RelTool takes a robtarget, Dx, Dy, Dz [\\Rx] [\\Ry] [\\Rz]")
    point = args[0]
    if type(point) is not Record or point.type != "ROBTARGET":
        point = compiler.coerce("ROBTARGET", point, where)
    offset = [num(a, where) for a in args[1:]]
    t, q = vec(point["TRANS"], "XYZ"), vec(point["ROT"], QUAT_KEYS)
    moved_t = [a + b for a, b in zip(t, posemath.quat_rotate(q, offset), strict=True)]
    turn = _intrinsic_xyz(*(num(kwargs.get(k, 0), where) for k in ("RX", "RY", "RZ")))
    moved = point.shallow()
    moved["TRANS"] = pos_record(moved_t)
    moved["ROT"] = orient_record(posemath.quat_multiply(q, turn))
    return moved


def move(kind: str, fr, args, kwargs, where) -> None:
    """MoveJ / MoveL (kind "joint" / "linear"): to a robtarget, or with a work object a conveyor moves."""
    compiler = fr.m.program.compiler
    no_motion_in_trap(fr, where, "MoveJ" if kind == "joint" else "MoveL")
    moving = tracking.coordinated(compiler, kwargs.get("WOBJ"), where)
    if moving is not None:  # a work object a conveyor moves (codegen/dialects/rapid/tracking.py)
        tracking.move(compiler, fr, kind, moving, args, kwargs, where)
        return
    tracking.leave(fr)
    timing = move_timing(args, kwargs, where)
    m, target = target_pose(compiler, args[0], kwargs.get("WOBJ"), where)
    tracking.check_axes(fr, target["EXTAX"], where, "move target")
    event = move_event(fr, kind, m, target, args, timing, where, wobj=kwargs.get("WOBJ"))
    fr.m.move(event, motionset.speed(fr.m, timing[0]), timing[1])


def move_j(fr, args, kwargs, where) -> None:
    move("joint", fr, args, kwargs, where)


def move_l(fr, args, kwargs, where) -> None:
    move("linear", fr, args, kwargs, where)


def move_c(fr, args, kwargs, where):
    """MoveC CirPoint, ToPoint, Speed, Zone, Tool [\\WObj] [\\V]: the TCP on the circle through where the
    previous motion ends, CirPoint and ToPoint; it takes the arc's length over the speed's v_tcp. The
    orientation is the start's along the arc (the interpreter's circular path) and ToPoint's at its end;
    the arm's joints are solved at ToPoint only (not along the arc)."""
    compiler = fr.m.program.compiler
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
    event = move_event(fr, "linear", m, target, rest, timing, where, wobj=kwargs.get("WOBJ"))
    event.settings["circle_point"] = [float(v) for v in via[:3, 3]]
    fr.m.move(event, motionset.speed(fr.m, timing[0]), timing[1], via=via)


def c_rob_t(fr, args, kwargs, where):
    """CRobT(\\Tool:=tool \\WObj:=wobj): the robtarget where the arm is now (where the clock finds it on
    the path of a move under way: in a TRAP, the cycle its interrupt came), for that tool in that work
    object. Without \\Tool or \\WObj the active ones: those of the latest move instruction (RAPID functions,
    CRobT, as recalled); before any move there are none here (an error)."""
    compiler = fr.m.program.compiler
    if args or set(kwargs) - {"TOOL", "WOBJ"}:
        raise RunError(f"{where}: CRobT takes \\Tool and \\WObj only")
    tool, wobj = kwargs.get("TOOL"), kwargs.get("WOBJ")
    if tool is None or "WOBJ" not in kwargs:
        active = fr.m.state.active
        if active is None:
            shown = "before any move (no move has made a tool and a work object the active ones)"
            raise RunError(f"{where}: CRobT takes \\Tool:= and \\WObj:= {shown}")
        tool = active[0] if tool is None else tool
        wobj = active[1] if "WOBJ" not in kwargs else wobj
    tool2flange = tool_matrix(tool, where)
    base2wobj = np.linalg.inv(wobj_matrix(compiler, wobj, where))
    tcp2base, active = tcp_now(fr.m)
    if tcp2base is None:
        raise RunError(f"{where}: CRobT: the arm's pose is not known here (no move to a pose yet)")
    pose = base2wobj @ tcp2base @ np.linalg.inv(active) @ tool2flange
    out = robtarget_from(pose, conf_now(fr.m), where)
    tracking.fill_axes(fr, out["EXTAX"])  # an active conveyor's position in its logical axis
    return out


def c_pos(fr, args, kwargs, where):
    """CPos(\\Tool \\WObj): the position (pos) of CRobT's robtarget."""
    return c_rob_t(fr, args, kwargs, where)["TRANS"]


def c_joint_t(fr, args, kwargs, where):
    """CJointT(): the arm's current joint angles (deg) as a jointtarget (RAPID functions)."""
    compiler = fr.m.program.compiler
    q = fr.m.arm.actual(where)
    out = compiler.coerce("JOINTTARGET", [[f32(v) for v in q], [f32(9e9)] * 6], where)
    tracking.fill_axes(fr, out["EXTAX"])  # an active conveyor's position in its logical axis
    return out


def move_abs_j(fr, args, kwargs, where):
    compiler = fr.m.program.compiler
    no_motion_in_trap(fr, where, "MoveAbsJ")
    target = args[0]
    if type(target) is not Record or target.type != "JOINTTARGET":
        target = compiler.coerce("JOINTTARGET", target, where)
    q = vec(target["ROBAX"], tuple(f"RAX_{i}" for i in range(1, 7)))
    posemath.check_finite(q, where, "joint target")
    tracking.check_axes(fr, target["EXTAX"], where, "joint target")
    tracking.leave(fr)
    speed, zone, tool = (move_setting(args, i) for i in (1, 2, 3))
    settings = {"speed": speed, "zone": zone, "tool": tool, "load": move_load(fr, args, where)}
    make_active(fr, args, kwargs.get("WOBJ"))
    mm_s, runs_ahead = move_timing(args, kwargs, where)
    settings["tcp_mm_s"], settings["zone_mm"] = mm_s, zone_radius(args[2] if len(args) > 2 else None)
    motionset.apply(fr.m, settings)
    event = MoveEvent("joint", None, int(where.split(":")[1]), settings, file=where.split(":")[0])
    fr.m.arm.to_joints(event, q, where)
    fr.m.move(event, motionset.speed(fr.m, mm_s), runs_ahead)


BUILTINS = {  # the RAPID functions and procedures the interpreter provides, by upper-case name
    "ORIENTZYX": orient_zyx,
    "EULERZYX": euler_zyx,
    "NORIENT": norient,
    "POSEMULT": pose_mult,
    "POSEINV": pose_inv,
    "POSEVECT": pose_vect,
    "OFFS": offs,
    "RELTOOL": rel_tool,
    "ERRWRITE": err_write,
    "SAVE": save,
    "UIMESSAGEBOX": ui_message_box,
    "STOP": pause,  # the program resumes at the next instruction when the operator presses start
    "EXIT": halt,
    "MOVEJ": move_j,
    "MOVEL": move_l,
    "MOVEABSJ": move_abs_j,
    "MOVEC": move_c,
    "CROBT": c_rob_t,
    "CJOINTT": c_joint_t,
    "CPOS": c_pos,
    "MAXROBSPEED": lambda fr, a, k, w: f32(VMAX_TCP),
}


def _intrinsic_xyz(rx: float, ry: float, rz: float) -> tuple[float, ...]:
    """The quaternion of turns about x, then the new y, then the new z (deg): Rx . Ry . Rz."""
    qx = posemath.quat_from_zyx_deg(0, 0, rx)
    qy = posemath.quat_from_zyx_deg(0, ry, 0)
    qz = posemath.quat_from_zyx_deg(rz, 0, 0)
    return posemath.quat_multiply(posemath.quat_multiply(qx, qy), qz)
