"""KRL system variables people read and set: path parameters, timers, flags, the arm's actual position (KSS 8)."""

from __future__ import annotations

import numpy as np

from codegen.dialects import posemath
from codegen.dialects.core.values import Record, RunError, f32
from codegen.dialects.krl.builtins import (
    UNINIT,
    XYZABC,
    cart,
    cart_matrix,
    frame,
    new_value,
    shown,
    type_name_of,
    xyzabc,
)
from codegen.dialects.krl.numbered import fresh_warning
from codegen.dialects.krl.position import base2robot
from codegen.poses import invert
from codegen.robot.config import FORMS

# Sources: KUKA, "System Variables for KUKA System Software 8.1, 8.2, 8.3 and 8.4" (V2, 2016), for the types
# and ranges; KUKA's BAS.SRC (KSS 8, BAS(#INITMOV)) for what the start section sets. What the manual does
# not say here is marked "assumed" and chosen so that a program relying on it fails rather than moves.
#
# name -> (type, size or None, default or None: no value until the program or BAS sets it)
TIMERS = 64  # $TIMER[1..64], $TIMER_STOP[1..64], $TIMER_FLAG[1..64] (KSS 8.x: 64 timers; 32 on KSS 5)
FLAGS = 1024  # $FLAG[1..1024]
AXES = 6
TABLE: dict[str, tuple[str, int | None, object]] = {
    "$VEL": ("VEL_STRUC", None, None),
    "$ACC": ("ACC_STRUC", None, None),
    "$APO": ("APO_STRUC", None, None),
    "$VEL_AXIS": ("INT", AXES, None),  # % of the axes' top speed (PTP)
    "$ACC_AXIS": ("INT", AXES, None),  # % of the axes' top acceleration (PTP)
    "$GEAR_JERK": ("INT", 12, None),  # recorded only: the trace has no dynamics
    "$COLLMON_TOL_PRO": ("INT", 12, None),  # recorded only: no collision detection here
    "$ADVANCE": ("INT", None, 3),  # 0..5 motions planned ahead (DEF_ADVANCE of $config.dat)
    "$OV_PRO": ("INT", None, 100),  # program override % (assumed 100: the operator's setting is not known)
    "$BWDSTART": ("BOOL", None, False),  # backward motion start: no effect (the interpreter runs forward)
    "$IPO_MODE": ("ENUM", None, "#BASE"),  # #TCP (an external TCP) is refused at the motion
    "$ACT_TOOL": ("INT", None, None),
    "$ACT_BASE": ("INT", None, None),
    "$ACT_EX_AX": ("INT", None, None),
    "$FLAG": ("BOOL", FLAGS, False),
    "$TIMER": ("INT", TIMERS, None),  # computed: ms
    "$TIMER_STOP": ("BOOL", TIMERS, None),  # computed
    "$TIMER_FLAG": ("BOOL", TIMERS, None),  # computed, read-only
    "$STOPMESS": ("BOOL", None, False),  # read-only: no stop message is ever pending here
    "$MODE_OP": ("ENUM", None, "#AUT"),  # read-only: the interpreter runs a program as in automatic mode (assumed)
    # the operating mode's outputs (KSS 8 system variables: $T1, $T2, $AUT, $EXT, BOOL, read-only), as $MODE_OP
    "$T1": ("BOOL", None, False),
    "$T2": ("BOOL", None, False),
    "$AUT": ("BOOL", None, True),
    "$EXT": ("BOOL", None, False),
    "$NUM_AX": ("INT", None, AXES),
    "$EX_AX_NUM": ("INT", None, 0),  # no external axes modelled
    "$WORKSPACE": ("WORKSPACE", 8, None),  # recorded only: a violation never stops the arm here
    "$JERK": ("JERK_STRUC", None, None),  # recorded only
    "$EX_AX_IGNORE": ("INT", None, None),  # recorded only
    "$SPL_ORI_JOINT_AUTO": ("ENUM", None, None),  # recorded only
    "$CIRC_MODE": ("CIRC_MODE", None, None),  # recorded only
    "$POS_ACT": ("E6POS", None, None),  # computed, read-only
    "$AXIS_ACT": ("E6AXIS", None, None),  # computed, read-only
    "$IN_HOME": ("BOOL", None, None),  # computed, read-only
    "$MOVE_BCO": ("BOOL", None, None),  # computed, read-only
    "$ROB_TIMER": ("INT", None, None),  # computed, read-only
    "$H_POS": ("E6AXIS", None, None),  # the home position ($IN_HOME): the inline form sets it, else XHOME
    # palletizing mode (BOOL): off on a fresh controller (assumed); switched on, the controller holds A4 and keeps
    # the flange horizontal, which the solver here does not model: TRUE is refused where it is set
    "$PAL_MODE": ("BOOL", None, False),
}
READ_ONLY = frozenset(
    {
        "$TIMER_FLAG",
        "$STOPMESS",
        "$MODE_OP",
        "$T1",
        "$T2",
        "$AUT",
        "$EXT",
        "$NUM_AX",
        "$EX_AX_NUM",
        "$POS_ACT",
        "$AXIS_ACT",
        "$IN_HOME",
        "$MOVE_BCO",
        "$ROB_TIMER",
    }
)
RECORDED_ONLY = frozenset(
    {
        "$GEAR_JERK",
        "$COLLMON_TOL_PRO",
        "$WORKSPACE",
        "$JERK",
        "$EX_AX_IGNORE",
        "$SPL_ORI_JOINT_AUTO",
        "$CIRC_MODE",
        "$BWDSTART",
    }
)
# Not modelled, refused by name where a program uses them (what they would do is not in the trace)
REFUSED = {
    "$ANIN": "analog inputs are not modelled",
    "$ANOUT": "analog outputs are not modelled",
    "$CYCFLAG": "cyclical flags (an expression the controller evaluates every cycle) are not modelled",
    "$WORKSTATE": "workspace monitoring is not modelled",
    "$ERR": "error handling (ON_ERROR_PROCEED, $ERR) is not modelled",
    "$OUT_C": "outputs set in the main run ($OUT_C) are not modelled",
    "$PRO_IP": "the program pointer is not modelled",
}
H_POS_TOL_DEG = 0.1  # $IN_HOME: the axes within this of $H_POS (assumed: the tolerance is machine data)
SHARED_STRUCTS = {
    "WORKSPACE": [
        *XYZABC,
        ("X1", "REAL"),
        ("Y1", "REAL"),
        ("Z1", "REAL"),
        ("X2", "REAL"),
        ("Y2", "REAL"),
        ("Z2", "REAL"),
        ("MODE", "ENUM"),
    ],
    "JERK_STRUC": [("CP", "REAL"), ("ORI", "REAL"), ("AX", "ANY")],
    "CIRC_MODE": [("AUX_PT", "ANY"), ("TARGET_PT", "ANY")],
}


def known(name: str) -> bool:
    return name in TABLE


def initial(name: str, structs: dict):
    """A system variable's value before the program sets it."""
    type_name, size, default = TABLE[name]
    if size is None:
        return default if default is not None else new_value(type_name, structs)
    return [default if default is not None else new_value(type_name, structs) for _ in range(size)]


# --- timers --------------------------------------------------------------------------------------------
# $TIMER[n] counts milliseconds while $TIMER_STOP[n] is FALSE; $TIMER_FLAG[n] is TRUE while $TIMER[n] >= 0.
# The count runs with the program's clock (the advance run's: reading or setting a timer does not stop the
# advance run, which is why KUKA's cycle-time example has a WAIT SEC 0 before it stops the timer; recalled).
# At the start every timer stands (stopped) at 0 (assumed: a timer keeps its value from program to program).


def _timers(m) -> list:
    timers = m.state.timers
    if timers is None:
        timers = m.state.timers = [(0.0, 0.0, True)] * TIMERS  # (ms at t0, t0 s, stopped)
    return timers


def timer_values(m) -> list[int]:
    now = m.clock
    return [round(v if stopped else v + (now - t0) * 1000.0) for v, t0, stopped in _timers(m)]


def set_timers(m, values: list, where: str) -> None:
    old, now, timers = timer_values(m), m.clock, list(_timers(m))
    for i, (new, was) in enumerate(zip(values, old, strict=True)):
        if new is not UNINIT and new != was:
            if isinstance(new, bool) or not isinstance(new, int):
                raise RunError(f"{where}: $TIMER[{i + 1}] takes an INT (ms), got {type_name_of(new)}")
            timers[i] = (float(new), now, timers[i][2])
    m.state.timers = timers


def set_timer_stops(m, values: list, where: str) -> None:
    now, timers = m.clock, list(_timers(m))
    for i, stop in enumerate(values):
        value, t0, stopped = timers[i]
        if not isinstance(stop, bool):
            raise RunError(f"{where}: $TIMER_STOP[{i + 1}] takes TRUE or FALSE")
        if stop and not stopped:
            timers[i] = (value + (now - t0) * 1000.0, now, True)
        elif not stop and stopped:
            timers[i] = (value, now, False)
    m.state.timers = timers


def timers_running(m) -> bool:
    return any(not stopped for _v, _t, stopped in _timers(m))


# --- the arm's actual position ---------------------------------------------------------------------------


def _tcp_now(fr, where: str, what: str) -> np.ndarray:
    """Where the TCP stands (robot's base frame, the active $TOOL): the end of the last move (the read stops
    the advance run: the arm has arrived)."""
    m = fr.m
    m.arrive(where)
    last = m.last_move
    if last is not None and last.tcp2base is None:
        m.arm.resolve()
    if last is None or last.tcp2base is None:
        raise RunError(
            f"{where}: {what}: the arm's position is not known here (before the first motion, or after a PTP to "
            "axis values without the arm's model: codegen run --robot)"
        )
    tcp = last.tcp2base
    tool_then, tool_now = m.state.tool_at_move, m.arm.tcp2flange
    if tool_then is not None and not np.array_equal(tool_then, tool_now):
        tcp = tcp @ invert(tool_then) @ tool_now  # the same flange, the tool set since
    return tcp


def pos_act(fr, where: str) -> Record:
    """$POS_ACT: the TCP in the active $BASE (E6POS; S and T where the arm's model gives the joints)."""
    tcp = _tcp_now(fr, where, "$POS_ACT")
    values = posemath.xyzabc_from_matrix(invert(base2robot(fr.m.state.sysvars)) @ tcp)
    out = {k: f32(v) for (k, _), v in zip(XYZABC, values, strict=True)}
    status = turn = UNINIT
    arm = fr.m.arm
    joints = arm.current(where) if arm.arm is not None else None
    if joints is not None:  # the configuration the arm stands in (Status, Turn)
        status, turn = (int(v) for v in FORMS["status_turn"].of(arm.arm, joints))
    return Record("E6POS", {**out, "S": status, "T": turn, **{f"E{i}": f32(0.0) for i in range(1, 7)}})


def axis_act(fr, where: str) -> Record:
    """$AXIS_ACT: the axes where the last move ended (deg): from the arm's model, or the last PTP's axis values."""
    m = fr.m
    m.arrive(where)
    joints = m.arm.current(where) if m.arm.arm is not None else None
    if joints is None and m.last_move is not None:
        joints = m.last_move.joints
    if joints is None:
        joints = m.arm.joints  # where the arm stood at the start (codegen run --start)
    if joints is None:
        raise RunError(
            f"{where}: $AXIS_ACT: the axes' position is not known here (before the first PTP to axis values: "
            "codegen run --start and --robot)"
        )
    axes = {f"A{i + 1}": f32(q) for i, q in enumerate(joints)}
    return Record("E6AXIS", {**axes, **{f"E{i}": f32(0.0) for i in range(1, 7)}})


def home_position(fr, where: str) -> Record:
    """$H_POS: the home position as the program set it (the HOME inline form: $H_POS = XHOME), else XHOME."""
    home = fr.m.state.sysvars.get("$H_POS") or fr.m.globals.get("XHOME", UNINIT)
    if not isinstance(home, Record):
        raise RunError(f"{where}: $H_POS: XHOME has no value ($config.dat)")
    return home


def in_home(fr, where: str) -> bool:
    """$IN_HOME: every axis within H_POS_TOL_DEG of $H_POS."""
    axes, home = axis_act(fr, where), home_position(fr, where)
    for i in range(1, AXES + 1):
        h = home[f"A{i}"]
        if h is UNINIT:
            raise RunError(f"{where}: $IN_HOME: XHOME.A{i} has no value ($config.dat)")
        if abs(float(axes[f"A{i}"]) - float(h)) > H_POS_TOL_DEG:
            return False
    return True


COMPUTED = {
    "$POS_ACT": pos_act,
    "$AXIS_ACT": axis_act,
    "$IN_HOME": in_home,
    "$H_POS": home_position,
    "$MOVE_BCO": lambda fr, where: fr.m.last_move is None,
    "$ROB_TIMER": lambda fr, where: round(fr.m.clock * 1000.0),
    "$TIMER": lambda fr, where: timer_values(fr.m),
    "$TIMER_STOP": lambda fr, where: [stopped for _v, _t, stopped in _timers(fr.m)],
    "$TIMER_FLAG": lambda fr, where: [v >= 0 for v in timer_values(fr.m)],
}


def read(fr, name: str, where: str, structs: dict):
    """A system variable's value now."""
    computed = COMPUTED.get(name)
    if computed is not None:
        return computed(fr, where)
    store = fr.m.state.sysvars
    value = store.get(name)
    if value is None:
        value = store[name] = initial(name, structs)
    fast = PATH_FIELDS.get(name)
    if fast is not None and fast[1] in store and (value[fast[0]] is UNINIT or float(value[fast[0]]) != store[fast[1]]):
        value = value.shallow()  # `$VEL.CP = x` / `$APO.CDIS = x` store the number alone (motion.py): the record too
        value[fast[0]] = f32(store[fast[1]])
        store[name] = value
    return value


PATH_FIELDS = {"$VEL": ("CP", "$VEL.CP"), "$APO": ("CDIS", "$APO.CDIS")}


def write(fr, name: str, value, where: str) -> None:
    """Store a system variable (the checks and the effects of the ones the interpreter models)."""
    m = fr.m
    if name in READ_ONLY:
        raise RunError(f"{where}: {name} is read-only")
    if name == "$TIMER":
        set_timers(m, value, where)
        return
    if name == "$TIMER_STOP":
        set_timer_stops(m, value, where)
        return
    if name == "$ADVANCE" and (isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 5):
        raise RunError(f"{where}: $ADVANCE takes 0..5, got {shown(value)}")
    if name == "$PAL_MODE" and value is True:
        what = "palletizing mode (A4 held, the flange kept horizontal)"
        raise RunError(f"{where}: $PAL_MODE = TRUE: {what} is not modelled")
    if name == "$OV_PRO" and (isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 100):
        raise RunError(f"{where}: $OV_PRO takes 0..100 (%), got {shown(value)}")
    m.state.sysvars[name] = value
    if name == "$VEL" and value["CP"] is not UNINIT:
        m.state.sysvars["$VEL.CP"] = float(value["CP"])
    elif name == "$APO" and value["CDIS"] is not UNINIT:
        m.state.sysvars["$APO.CDIS"] = float(value["CDIS"])
    elif name == "$VEL_AXIS" and value[0] is not UNINIT:
        m.state.sysvars["VEL_PTP"] = float(value[0])
    elif name == "$ACC_AXIS" and value[0] is not UNINIT:
        m.state.sysvars["ACC_PTP"] = float(value[0])
    if name == "$ACC" and value["CP"] is not UNINIT:
        m.state.sysvars["$ACC.CP"] = float(value["CP"])


def world() -> Record:
    return frame()


def tool_of(fr, where: str) -> Record:
    tool = fr.m.state.sysvars.get("$TOOL")
    if tool is None:
        raise RunError(f"{where}: $TOOL has no value here (the tool active when the program started is not known)")
    return tool


def set_tool(fr, value, where: str) -> None:
    fresh_warning(fr.m, value)
    tool = cart(value, where)
    posemath.check_finite(xyzabc(tool), where, "$TOOL")
    fr.m.state.sysvars["$TOOL"] = tool
    fr.m.arm.tcp2flange = cart_matrix(tool)
