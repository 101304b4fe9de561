"""RAPID conveyor tracking (ABB's Conveyor Tracking option): ActUnit, DeactUnit, WaitWObj, DropWObj, moves in a
work object the conveyor moves."""

from __future__ import annotations

import math

import numpy as np

from codegen.dialects import posemath
from codegen.dialects.core.ramp import travel_seconds
from codegen.dialects.core.values import Record, RunError, f32
from codegen.dialects.rapid import motionset
from codegen.dialects.rapid.errors import ERROR_NUMBERS, RapidError
from codegen.dialects.rapid.motion import frame_matrix, move_event, move_timing
from codegen.dialects.rapid.predefined import WOBJ0
from codegen.dialects.rapid.types import QUAT_KEYS, num, type_text, vec

UNUSED = 9e9  # an external axis' value the controller reads as "not used" (RAPID data types, extjoint: 9E9)
AXIS_SLOTS = {7 + i: f"EAX_{c}" for i, c in enumerate("ABCDEF")}  # logical axis -> extjoint component

# Sources (the option's manual, "Application manual - Conveyor tracking", 3HAC16587-1, was not readable here):
# - ABB, "Application manual - MultiMove" (3HAC021272-001), coordinated work objects: a work object the robot does
#   not hold whose user frame a mechanical unit moves has ufprog FALSE and ufmec the unit's name; public programs
#   declare the conveyor's so ([FALSE, FALSE, "CNV1", uframe, oframe]), as PERS or TASK PERS.
# - Public RAPID programs (code index: WaitWObj, DropWObj): ActUnit CNV1 activates the conveyor's unit; WaitWObj
#   wobj [\RelDist:=mm] waits for an object of the conveyor's queue and connects the work object to it: from then on
#   a move with \WObj:=wobj follows the conveyor, also a fine point (the arm "stands" on the moving object while the
#   program goes on: the grip while following); DropWObj wobj disconnects it; DeactUnit CNV1.
# - The signal descriptions of the conveyor's encoder interface (a public RAPID library quotes them): the queue
#   holds the objects that passed the sync switch and have not left the start window; an object that passes out of
#   the start window is lost (c1PassedStWin) and, "if the main process is waiting in a WaitWObj instruction, the
#   program pointer will be moved to the nearest error handler"; c1RemAllPObj empties the queue of objects not
#   connected, c1Rem1PObj removes the first one.
# - RobotStudio's API (ConveyorConnection): CountsPerMeter (a whole number), QueueTrackingDistance,
#   MinimumDistance, MaximumDistance of a conveyor; ConnectedObjectPosition.
# Modelled so (the simulated unit: codegen/sim/belt.py TrackingUnit): the unit moves its base frame along its own
# x axis by the connected object's travel since its sync (its position; 0 with none connected, as after DropWObj);
# a coordinated work object's frame is unit frame . Trans(position, 0, 0) . oframe: "When coordinated external axes
# are used (ufprog is FALSE), the user coordinate system is defined in the system parameters" (ABB, RAPID reference /
# Basic Characteristics, wobjdata, uframe), so the program's uframe is not used (the MultiMove manual's coordinated
# work object has an identity uframe and its offset in the oframe). WaitWObj connects the
# oldest queued object once it is inside the start window (and \RelDist past the sync point); an object that left
# the start window while WaitWObj waited for it raises ERR_CNV_DROPPED (the error's name for this case is not
# confirmed); WaitWObj on a work object still connected: ERR_CNV_CONNECT; a unit not active (no ActUnit):
# ERR_CNV_NOT_ACT. WaitWObj \MaxTime:=s: no object connected within s seconds raises ERR_WAIT_MAXTIME (RAPID
# reference, WaitWObj, as recalled: the manual's text was not readable here), the queue left as it was; without
# \MaxTime a wait for an object that never comes is refused (it would wait forever). An active unit is a joint of
# the controller: its logical axis (7..12: eax_a..eax_f of a robtarget or jointtarget) holds its position, so a
# move while it is active to a target whose slot is 9E+09 (unused) is refused (a public pick-from-belt program in
# the code index writes 0 in eax_f of every robtarget it moves to while CNV1 is active, 9E+09 in the others; the
# refusal itself is assumed, not confirmed in ABB's manual), and CJointT and CRobT read the unit's position (mm: the
# connected object's travel since its sync, 0 with none connected) there. A move in the coordinated work object ends
# where the object is when the move ends (its length measured relative to the object); the arm then follows the
# object (a fine point too) until a move in another work object or DropWObj. Assumed: a unit the controller's
# configuration does not have (the simulated belt's unit) is refused; DeactUnit with an object connected drops it.


class MecUnit:
    """A mechanical unit's name as RAPID's predefined mecunit data (CNV1 ... CNV6: the conveyors' units)."""

    def __init__(self, name: str) -> None:
        self.name = name

    def __repr__(self) -> str:
        return self.name


MECUNITS = {f"CNV{i}": MecUnit(f"CNV{i}") for i in range(1, 7)}


def _error(name: str, message: str) -> RapidError:
    return RapidError(ERROR_NUMBERS[name], message)


def _unit_of_name(fr, name: str, where: str):
    for device in fr.m.devices:
        find = getattr(device, "mechanical_unit", None)
        unit = None if find is None else find(name)
        if unit is not None:
            return unit
    raise RunError(f"{where}: mechanical unit {name} is not in this controller's configuration")


def _mecunit(value, where: str) -> str:
    if not isinstance(value, MecUnit):
        raise RunError(f"{where}: expected a mechanical unit (mecunit), got {type_text(value)}")
    return value.name


def coordinated(compiler, wobj, where: str) -> Record | None:
    """The work object when a mechanical unit moves it (ufprog FALSE, ufmec a unit's name), else None."""
    if wobj is None or wobj is WOBJ0 or not isinstance(wobj, Record):
        return None
    wobj = compiler.coerce("WOBJDATA", wobj, where)
    if wobj["UFPROG"] or not str(wobj["UFMEC"]):
        return None
    if wobj["ROBHOLD"]:
        raise RunError(f"{where}: a work object held by the robot is not supported")
    return wobj


def _active(fr, wobj: Record, where: str):
    name = str(wobj["UFMEC"]).upper()
    unit = fr.m.state.units.get(name)
    if unit is None:
        _unit_of_name(fr, name, where)  # a unit the configuration does not have: refused by name
        raise _error("ERR_CNV_NOT_ACT", f"{where}: mechanical unit {wobj['UFMEC']} is not active (ActUnit)")
    return unit


class Follow:
    """The arm on a connected object (Machine.tracking): the last commanded pose relative to the unit's moving
    frame, carried with it."""

    def __init__(self, unit, relative: np.ndarray) -> None:
        self.unit, self.relative = unit, relative

    def frame(self, t: float) -> np.ndarray:
        moving = self.unit.settings.frame.copy()
        moving[:3, 3] += moving[:3, 0] * self.unit.position_mm(t)
        return moving

    def pose_now(self, machine) -> np.ndarray:
        return self.frame(machine.clock) @ self.relative


def leave(fr) -> None:
    """A move in another work object, or DropWObj: the arm stops following where the object carried it."""
    follow = fr.m.tracking
    if isinstance(follow, Follow):
        fr.m._last_tcp2base = follow.frame(max(fr.m.clock, fr.m.arm_until)) @ follow.relative
        fr.m.tracking = None


def move(compiler, fr, kind: str, wobj: Record, args, kwargs, where: str) -> None:
    """MoveJ / MoveL in a coordinated work object: the target relative to the unit's moving frame, reached where
    the frame is at the move's end (moves relative to the object take their relative length over the speed)."""
    unit = _active(fr, wobj, where)
    timing = move_timing(args, kwargs, where)
    target = args[0]
    if type(target) is not Record or target.type != "ROBTARGET":
        target = compiler.coerce("ROBTARGET", target, where)
    t, q = vec(target["TRANS"], "XYZ"), vec(target["ROT"], QUAT_KEYS)
    posemath.check_finite(t + q, where, "move target")
    check_axes(fr, target["EXTAX"], where, "move target")
    # the user frame is the unit's (its system parameters): the program's uframe is not used; the object frame in it
    relative = frame_matrix(wobj["OFRAME"]) @ posemath.matrix_from_abb(t + q)
    follow = Follow(unit, relative)
    machine = fr.m
    start = max(machine.clock, machine.arm_until)
    before = machine.tracking.pose_now(machine) if machine.tracking is not None else machine.tool_pose()
    if isinstance(machine.tracking, Follow) and machine.tracking.unit is not unit:
        leave(fr)
    now = None if before is None else np.linalg.inv(follow.frame(start)) @ before
    seconds = travel_seconds(now, relative, motionset.speed(machine, timing[0]))
    pose = follow.frame(start + seconds) @ relative
    event = move_event(fr, kind, pose, target, args, timing, where, wobj=wobj)
    machine.tracking = None
    machine.move(event, motionset.speed(machine, timing[0]), timing[1], seconds=seconds)
    machine.tracking = follow


def act_unit(fr, args, kwargs, where):
    if len(args) != 1 or kwargs:
        raise RunError(f"{where}: ActUnit takes a mechanical unit")
    name = _mecunit(args[0], where)
    unit = _unit_of_name(fr, name, where)
    units = dict(fr.m.state.units)
    units[name.upper()] = unit
    unit.active = True
    fr.m.state.units = units


def deact_unit(fr, args, kwargs, where):
    if len(args) != 1 or kwargs:
        raise RunError(f"{where}: DeactUnit takes a mechanical unit")
    name = _mecunit(args[0], where).upper()
    units = dict(fr.m.state.units)
    unit = units.pop(name, None)
    if unit is not None:
        fr.m.arrive(where)
        if isinstance(fr.m.tracking, Follow) and fr.m.tracking.unit is unit:
            leave(fr)
        unit.drop(fr.m.clock)
        unit.active = False
    fr.m.state.units = units


def _wobj_arg(compiler, args, where: str, name: str) -> Record:
    wobj = coordinated(compiler, args[0], where) if args else None
    if wobj is None:
        raise RunError(f"{where}: {name} takes a work object a mechanical unit moves (ufprog FALSE, ufmec its unit)")
    return wobj


def check_axes(fr, extax: Record, where: str, what: str) -> None:
    """A move's target while units are active: each active unit's logical axis must hold a value, not 9E+09."""
    for unit in fr.m.state.units.values():
        slot = AXIS_SLOTS[unit.settings.axis]
        if abs(float(extax[slot])) >= 0.99 * UNUSED:
            raise RunError(
                f"{where}: {what}: {slot.lower()} is 9E+09 (unused), but it is the logical axis "
                f"{unit.settings.axis} of the active unit {unit.name}: give it the unit's position (0 or as taught)"
            )


def fill_axes(fr, extax: Record) -> Record:
    """CJointT / CRobT: each active unit's position (mm) in its logical axis' slot."""
    for unit in fr.m.state.units.values():
        extax[AXIS_SLOTS[unit.settings.axis]] = f32(unit.position_mm(fr.m.clock))
    return extax


def wait_wobj(fr, args, kwargs, where) -> None:
    if len(args) != 1 or set(kwargs) - {"RELDIST", "RELPOS", "MAXTIME"}:
        raise RunError(f"{where}: WaitWObj takes a work object [\\RelDist] [\\MaxTime]")
    if "RELPOS" in kwargs:
        raise RunError(f"{where}: WaitWObj \\RelPos is not modelled")
    wobj = _wobj_arg(fr.m.program.compiler, args, where, "WaitWObj")
    unit = _active(fr, wobj, where)
    if unit.connected is not None:
        raise _error("ERR_CNV_CONNECT", f"{where}: WaitWObj: the work object is connected already (DropWObj)")
    machine = fr.m
    rel = num(kwargs["RELDIST"], where) if "RELDIST" in kwargs else 0.0
    until = machine.clock + num(kwargs["MAXTIME"], where) if "MAXTIME" in kwargs else math.inf
    seq, due, connected = unit.connect(machine.clock, rel, until)  # (the object's part, when, connected or lost)
    if connected is None:
        machine.elapse(until - machine.clock, where)
        raise _error("ERR_WAIT_MAXTIME", f"{where}: WaitWObj \\MaxTime: no object connected in time")
    if seq is None:
        raise RunError(f"{where}: WaitWObj waits for an object that never comes (waits forever)")
    machine.elapse(due - machine.clock, where)
    if not connected:
        raise _error("ERR_CNV_DROPPED", f"{where}: WaitWObj: the object left the start window")


def drop_wobj(fr, args, kwargs, where) -> None:
    if len(args) != 1 or kwargs:
        raise RunError(f"{where}: DropWObj takes a work object")
    wobj = _wobj_arg(fr.m.program.compiler, args, where, "DropWObj")
    unit = _active(fr, wobj, where)
    if isinstance(fr.m.tracking, Follow) and fr.m.tracking.unit is unit:
        leave(fr)
    unit.drop(fr.m.clock)


BUILTINS = {"ACTUNIT": act_unit, "DEACTUNIT": deact_unit, "WAITWOBJ": wait_wobj, "DROPWOBJ": drop_wobj}
