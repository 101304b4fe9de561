"""RAPID motion helpers: tool, work object and target poses, move events, circles, speeds and zones, the TCP now."""

from __future__ import annotations

import math

import numpy as np

from codegen.dialects import posemath
from codegen.dialects.core.machine import MoveEvent
from codegen.dialects.core.values import Record, RunError, f32
from codegen.dialects.rapid import motionset
from codegen.dialects.rapid.predefined import TOOL0, WOBJ0, name_of
from codegen.dialects.rapid.types import QUAT_KEYS, num, type_text, vec
from codegen.poses import rotmat_from_quat
from codegen.world import loads

QUATERNION_TOLERANCE = 1e-5  # assumed: RAPID rejects an unnormalised orientation in a move


def move_load(fr, args, where: str) -> tuple | None:
    """The move's tooldata becomes the active tool: its TCP for the arm, its load (with the payload in force) for
    the trace. tool0 is the flange."""
    tool = args[3] if len(args) > 3 else None
    if tool is TOOL0:
        fr.m.arm.tcp2flange = np.eye(4)
        return None
    last = _LAST_TOOL
    if tool is last[0]:  # the same record as the last move's (records never change in place): the same tool
        tcp2flange, tool_load = last[1], last[2]
    else:
        tcp2flange, tool_load = _tool(tool, where)
        _remember_tool(tool, tcp2flange, tool_load)
    fr.m.arm.tcp2flange = tcp2flange
    return with_payload(fr.m, tool_load)


def _tool(tool, where: str) -> tuple[np.ndarray, tuple]:
    """A tooldata's TCP in the flange frame (read-only: shared by the moves that name the same record) and its
    loaddata's numbers (mass, cog, aom, moments), or RunError."""
    if not isinstance(tool, Record) or tool.type != "TOOLDATA":
        raise RunError(f"{where}: the move names no tooldata")
    if not tool["ROBHOLD"]:
        raise RunError(f"{where}: a stationary tool (robhold FALSE) is not supported")
    frame = tool["TFRAME"]
    pose7 = vec(frame["TRANS"], "XYZ") + vec(frame["ROT"], QUAT_KEYS)
    posemath.check_finite(pose7, where, "tooldata tframe")
    tcp2flange = posemath.matrix_from_abb(pose7)
    tcp2flange.flags.writeable = False
    load = tool["TLOAD"]
    mass = float(load["MASS"])
    if not mass > 0:
        raise RunError(f"{where}: a tool the robot holds must have a mass above 0 kg (tooldata tload)")
    moments = [float(load[k]) for k in ("IX", "IY", "IZ")]
    return tcp2flange, (mass, *vec(load["COG"], "XYZ"), *vec(load["AOM"], QUAT_KEYS), *moments)


# (the tooldata record, its TCP, its loaddata's numbers) of the last move, held so that its identity stays its own
_LAST_TOOL: tuple = (object(), None, None)


def _remember_tool(tool: Record, tcp2flange: np.ndarray, tool_load: tuple) -> None:
    global _LAST_TOOL
    _LAST_TOOL = (tool, tcp2flange, tool_load)


NO_PAYLOAD_KG = 0.001  # load0's mass: GripLoad load0 (or as light) leaves no payload


def _principal(mass: float, cog: list, aom: list, moments: list) -> loads.Load:
    """A loaddata: mass, cog, aom (the principal axes' orientation, a quaternion; all zero counts as none) and the
    moments ix, iy, iz about them (targets/abb.toml cites the form)."""
    axes = np.eye(3) if not any(aom) else rotmat_from_quat(aom)
    return loads.from_principal(mass, cog, axes, moments)


def with_payload(machine, tool_load: tuple) -> tuple:
    """The load at the flange as verify compares it (codegen.world.loads.Load.flat): the tool's (tload: centre of
    gravity and axes of moment in the wrist frame; tool_load its mass, cog, aom and moments) with the payload
    GripLoad put in force (its centre of gravity and axes of moment in the tool frame: RAPID Reference Manual,
    loaddata), one mass, centre and tensor."""
    grip = (motionset.current(machine) or {}).get("gripload")
    if grip is None or grip["mass"] <= NO_PAYLOAD_KG * (1.0 + 1e-6):  # load0 as a float32 num holds it
        return _tool_flat(*tool_load)
    payload = (grip["mass"], *grip["cog"], *grip["aom"], *grip["moments"])
    return _with_payload_flat(*tool_load, *payload, *machine.arm.tcp2flange.ravel().tolist())


@loads.Remembered
def _tool_flat(*loaddata: float) -> tuple:
    return _loaddata(loaddata).flat()


@loads.Remembered
def _with_payload_flat(*numbers: float) -> tuple:
    """The tool's loaddata (11 numbers), the payload's (11) and the TCP in the flange frame (16, row by row)."""
    tcp2flange = np.array(numbers[22:]).reshape(4, 4)
    return loads.combined(_loaddata(numbers[:11]), _loaddata(numbers[11:22]).moved(tcp2flange)).flat()


def _loaddata(numbers) -> loads.Load:
    """mass, cog (3), aom (4), moments (3) as a Load."""
    return _principal(numbers[0], list(numbers[1:4]), list(numbers[4:8]), list(numbers[8:11]))


def no_motion_in_trap(fr, where: str, name: str) -> None:
    """A TRAP runs between two cycles of the motion it interrupts: a motion or a wait there is not modelled
    (the controller allows moves in a TRAP with StorePath / RestoPath; the interpreter does not)."""
    trap = fr.m.state.trap
    if trap is not None:
        raise RunError(f"{where}: {name} in TRAP {trap}: a TRAP here may not move the arm or wait")


def frame_matrix(frame: Record) -> np.ndarray:
    """A pose record (trans, rot) as a 4x4 matrix (mm)."""
    return posemath.matrix_from_abb(vec(frame["TRANS"], "XYZ") + vec(frame["ROT"], QUAT_KEYS))


def wobj_matrix(compiler, wobj, where: str) -> np.ndarray:
    """A work object's frame in the base frame: uframe . oframe (wobj0, or none given: the identity)."""
    if wobj is None or wobj is WOBJ0:
        return np.eye(4)
    if not isinstance(wobj, Record):
        raise RunError(f"{where}: expected wobjdata, got {type_text(wobj)}")
    wobj = compiler.coerce("WOBJDATA", wobj, where)
    if wobj["ROBHOLD"]:
        raise RunError(f"{where}: a work object held by the robot is not supported")
    if not wobj["UFPROG"]:
        raise RunError(f"{where}: a work object with a moving user frame (ufprog FALSE) is not supported")
    return frame_matrix(wobj["UFRAME"]) @ frame_matrix(wobj["OFRAME"])


def tool_matrix(tool, where: str) -> np.ndarray:
    """A tooldata's TCP in the flange frame (tool0: the flange)."""
    if tool is TOOL0:
        return np.eye(4)
    if not isinstance(tool, Record) or tool.type != "TOOLDATA":
        raise RunError(f"{where}: expected tooldata, got {type_text(tool)}")
    matrix = frame_matrix(tool["TFRAME"])
    posemath.check_finite(list(matrix[:3, 3]), where, "tooldata tframe")
    return matrix


def target_pose(compiler, target, wobj, where: str) -> tuple[np.ndarray, Record]:
    """A robtarget in its work object: (tcp2base, the robtarget record)."""
    if type(target) is not Record or target.type != "ROBTARGET":
        target = compiler.coerce("ROBTARGET", target, where)
    t = vec(target["TRANS"], "XYZ")
    q = vec(target["ROT"], QUAT_KEYS)
    posemath.check_finite(t + q, where, "move target")
    q1, q2, q3, q4 = q
    norm = math.sqrt(q1 * q1 + q2 * q2 + q3 * q3 + q4 * q4)
    if abs(norm - 1.0) > QUATERNION_TOLERANCE:
        raise RunError(f"{where}: orientation not normalised (|q| = {norm:.9f})")
    m = posemath.matrix_from_abb(t + q)
    if wobj is not None and wobj is not WOBJ0:  # tcp2base = uframe . oframe . target (wobj0: identity)
        m = wobj_matrix(compiler, wobj, where) @ m
    return m, target


def move_setting(args, i: int) -> str:
    """A predefined speeddata, zonedata or tooldata by its name (upper case); any other value as 'custom'."""
    return (name_of(args[i]) if len(args) > i else None) or "custom"


def make_active(fr, args, wobj) -> None:
    """The move's tool and work object become the active ones (CRobT and CPos without \\Tool or \\WObj)."""
    fr.m.state.active = (args[3] if len(args) > 3 else None, wobj)


def move_event(
    fr, kind: str, m: np.ndarray, target: Record, args, timing, where: str, solve=True, wobj=None
) -> MoveEvent:
    """The MoveEvent of a move to m (args: the target, speed, zone and tool as MoveJ / MoveL take them), its
    tool (and work object) made the active ones and (solve) its joints left to the arm by the configuration rules."""
    make_active(fr, args, wobj)
    speed, zone, tool = (move_setting(args, i) for i in (1, 2, 3))
    settings = {"speed": speed, "zone": zone, "tool": tool, "load": move_load(fr, args, where)}
    settings["tcp_mm_s"], settings["zone_mm"] = timing[0], zone_radius(args[2] if len(args) > 2 else None)
    motionset.apply(fr.m, settings)
    event = MoveEvent(kind, m, int(where.split(":")[1]), settings, file=where.split(":")[0])
    if solve:
        solve_event(fr, kind, event, target, where)
    return event


def solve_event(fr, kind: str, event: MoveEvent, target: Record, where: str) -> None:
    """The move's joints by the controller's configuration rules (ConfJ / ConfL), solved with the run's."""
    conf = vec(target["ROBCONF"], ("CF1", "CF4", "CF6", "CFX"))
    check = fr.m.state.configuration_checks.get("CONFJ" if kind == "joint" else "CONFL", True)
    robconf = tuple(int(v) for v in conf)
    if kind == "joint" and check:  # ConfJ on (the default): the robot moves to the programmed configuration
        fr.m.arm.to_pose(event, where, "confdata", robconf)
    elif kind == "joint":  # ConfJ off: the closest configuration
        fr.m.arm.to_pose(event, where, "nearest")
    else:  # linear: the closest configuration; ConfL on: it must be the programmed one at the end
        fr.m.arm.to_pose(event, where, "keep", check=robconf if check else None)


# MoveC's limits (RAPID instructions, MoveC, as recalled, not confirmed here): the circle point and the end
# at least about 0.1 mm from the start and from each other, and an angle of at least about 1 deg between
# them as seen from the start (else the circle is not defined well enough: the controller refuses it). The
# largest arc one MoveC may run is not checked (a 240 deg limit is recalled, not confirmed).
CIRCLE_MIN_MM = 0.1
CIRCLE_MIN_DEG = 1.0


def check_circle(start: np.ndarray | None, via: np.ndarray, end: np.ndarray, where: str) -> None:
    if start is None:  # where the previous motion ends is not known while the program runs (a joint target)
        return
    p0, p1, p2 = start[:3, 3], via[:3, 3], end[:3, 3]
    for a, b, what in (
        (p0, p1, "CirPoint from the start"),
        (p0, p2, "ToPoint from the start"),
        (p1, p2, "CirPoint from ToPoint"),
    ):
        if np.linalg.norm(b - a) < CIRCLE_MIN_MM:
            raise RunError(f"{where}: MoveC: {what} is closer than {CIRCLE_MIN_MM} mm: no circle")
    u, v = p1 - p0, p2 - p0
    cos = float(u @ v) / float(np.linalg.norm(u) * np.linalg.norm(v))
    if math.degrees(math.acos(max(-1.0, min(1.0, cos)))) < CIRCLE_MIN_DEG:
        raise RunError(f"{where}: MoveC: the start, CirPoint and ToPoint lie (nearly) on a line: no circle")


def tcp_now(machine) -> tuple[np.ndarray | None, np.ndarray]:
    """(tcp2base, tcp2flange): the active tool's TCP where the clock finds the arm, and that tool."""
    watching = machine.watching
    if watching is not None:
        tcp2base, tcp2flange = watching.pose_at(machine.clock)
        if tcp2base is not None:
            return tcp2base, tcp2flange
    machine.arm.resolve()  # a joint target's pose is known once its move is solved
    return machine.pose_now(), machine.arm.tcp2flange


def conf_now(machine) -> tuple[int, int, int, int]:
    """The arm's configuration (cf1, cf4, cf6, cfx) where it stands; [0, 0, 0, 0] while it moves or without
    an arm model (the interpreter solves joints at the moves' ends only)."""
    if machine.arm.arm is None or machine.moving:
        return (0, 0, 0, 0)
    from codegen.robot.config import FORMS

    joints = machine.arm.current("CRobT")
    return (0, 0, 0, 0) if joints is None else tuple(int(v) for v in FORMS["confdata"].of(machine.arm.arm, joints))


def robtarget_from(pose: np.ndarray, conf, where: str) -> Record:
    """A 4x4 pose as a robtarget (external axes unused: 9E9)."""
    quat = posemath.quat_from_rotmat(tuple(pose[:3, :3].ravel()))
    trans = [f32(v) for v in pose[:3, 3]]
    return Record(
        "ROBTARGET",
        {
            "TRANS": Record("POS", dict(zip("XYZ", trans, strict=True))),
            "ROT": Record("ORIENT", dict(zip(QUAT_KEYS, (f32(v) for v in quat), strict=True))),
            "ROBCONF": Record("CONFDATA", dict(zip(("CF1", "CF4", "CF6", "CFX"), (f32(v) for v in conf), strict=True))),
            "EXTAX": Record("EXTJOINT", {f"EAX_{c}": f32(9e9) for c in "ABCDEF"}),
        },
    )


def zone_radius(zone) -> float:
    """The TCP zone of a move in mm: 0 for a stop point (fine, or a zonedata with finep), else its pzone_tcp."""
    if isinstance(zone, Record) and zone.type == "ZONEDATA":
        return 0.0 if zone["FINEP"] else float(zone["PZONE_TCP"])
    return 0.0


def speed_of(speed_arg, kwargs, where: str) -> float:
    """A move's TCP speed (mm/s): the speeddata's v_tcp (a predefined vN: N, vmax: VMAX_TCP), or \\V."""
    if isinstance(speed_arg, Record) and speed_arg.type == "SPEEDDATA":
        speed = float(speed_arg["V_TCP"])
    else:
        raise RunError(f"{where}: the move's speed is not a speeddata ({type_text(speed_arg)})")
    if "V" in kwargs:
        speed = num(kwargs["V"], where)
    if not speed > 0:
        raise RunError(f"{where}: the move's TCP speed must be above 0 mm/s, got {speed:g}")
    return speed


def move_timing(args, kwargs, where: str) -> tuple[float, bool]:
    """A move's TCP speed (mm/s) and whether the program runs ahead of it (a fly-by zone)."""
    speed = speed_of(args[1] if len(args) > 1 else None, kwargs, where)
    zone = args[2] if len(args) > 2 else None
    if isinstance(zone, Record) and zone.type == "ZONEDATA":
        return speed, not zone["FINEP"]
    raise RunError(f"{where}: the move's zone is not a zonedata ({type_text(zone)})")
