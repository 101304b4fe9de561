"""RAPID motion settings: AccSet, VelSet, SingArea, ConfJ, ConfL, GripLoad, recorded in each later move's settings."""

from __future__ import annotations

from collections.abc import Callable

from codegen.dialects.core.values import RunError
from codegen.dialects.rapid.arguments import split_args
from codegen.dialects.rapid.types import QUAT_KEYS, num, rec, vec

# Sources: ABB, "Technical reference manual - RAPID Instructions, Functions and Data types" (RobotWare 6/7),
# AccSet, VelSet, SingArea, ConfJ, ConfL, GripLoad, as recalled (the manual's text was not readable during this
# work; the ranges are uncertain and not checked beyond their sign):
# - AccSet Acc, Ramp [\FinePointRamp]: acceleration and its ramp in % of the normal values (default 100, 100);
# - VelSet Override, Max: every programmed speed in % (default 100) and the TCP speed at most Max mm/s;
# - SingArea \Wrist | \Off: the wrist may change orientation slightly near singularities (\Wrist) or not (\Off);
# - ConfJ / ConfL \On | \Off: the configuration check of joint / linear moves (on by default);
# - GripLoad Load: the payload the tool holds (loaddata; load0: none).
# The interpreter has no acceleration model: AccSet changes no time here. VelSet scales a move's duration (its
# recorded tcp_mm_s stays the programmed speed). SingArea is recorded only (the interpreter's arm has no
# singularity handling to switch).
#
# MoveEvent.settings keys this module adds, from the instruction on, on every later move of the run (absent while
# the program has not run the instruction; `line` is the instruction's line):
#   "accset":   {"acc": %, "ramp": %, "line": n}
#   "velset":   {"override": %, "max": mm/s, "line": n}
#   "singarea": {"mode": "wrist" | "off", "line": n}
#   "confj", "confl": {"on": bool, "line": n}
#   "gripload": {"mass": kg, "cog": [x, y, z] mm, "aom": [q1..q4], "moments": [ix, iy, iz] kg m2, "line": n}


def current(m) -> dict | None:
    return m.state.settings


def _record(fr, key: str, value: dict, where: str) -> None:
    m = fr.m
    line = int(where.split(":")[1]) if where.count(":") >= 2 else 0
    settings = dict(m.state.settings or {})  # a new dict: the trace keeps the one in force at the end
    settings[key] = {**value, "line": line}
    m.state.settings = settings
    m.trace.motion_settings = settings  # those in force when the run ends (a routine's caller goes on with them)


def acc_set(fr, args, kwargs, where) -> None:
    if len(args) != 2 or set(kwargs) - {"FINEPOINTRAMP"}:
        raise RunError(f"{where}: AccSet takes Acc and Ramp (%) [\\FinePointRamp]")
    acc, ramp = num(args[0], where), num(args[1], where)
    if not (acc > 0 and ramp > 0):
        raise RunError(f"{where}: AccSet {acc:g}, {ramp:g}: both must be above 0 %")
    _record(fr, "accset", {"acc": acc, "ramp": ramp}, where)


def vel_set(fr, args, kwargs, where) -> None:
    if len(args) != 2 or kwargs:
        raise RunError(f"{where}: VelSet takes Override (%) and Max (mm/s)")
    override, top = num(args[0], where), num(args[1], where)
    if not (override > 0 and top > 0):
        raise RunError(f"{where}: VelSet {override:g}, {top:g}: both must be above 0")
    _record(fr, "velset", {"override": override, "max": top}, where)
    fr.m.state.velset = (override / 100.0, top)


def sing_area(fr, args, kwargs, where) -> None:
    modes = set(kwargs) & {"WRIST", "OFF"}
    if args or len(modes) != 1 or set(kwargs) - modes:
        raise RunError(f"{where}: SingArea takes \\Wrist or \\Off")
    _record(fr, "singarea", {"mode": modes.pop().lower()}, where)


def configuration_check(name: str):
    """ConfJ \\On / \\Off, ConfL \\On / \\Off: the configuration check of MoveJ / MoveL (on by default)."""
    shown = {"CONFJ": "ConfJ", "CONFL": "ConfL"}[name]

    def run(fr, args, kwargs, where):
        switches = set(kwargs)
        if len(switches & {"ON", "OFF"}) != 1 or args or switches - {"ON", "OFF"}:
            raise RunError(f"{where}: {shown} takes \\On or \\Off")
        fr.m.state.configuration_checks[name] = "ON" in switches
        _record(fr, name.lower(), {"on": "ON" in switches}, where)

    return run


def grip_load(compiler, node, args_node) -> Callable:
    """GripLoad Load: its syntax takes "< persistent (PERS) of loaddata >" (RAPID Instructions, GripLoad, as
    recalled: a CONST or VAR loaddata, or an aggregate, is refused when the module is loaded)."""
    positional, named = split_args(compiler, node, args_node, set())
    if len(positional) != 1 or named:
        compiler.fail(node, "GripLoad takes one loaddata")
    arg = positional[0]
    if getattr(arg, "data", None) != "var":  # a parse tree's variable (lark's Tree; not imported here)
        compiler.fail(node, "GripLoad takes a persistent (PERS) loaddata, not a value")
    storage = compiler.storage.get(compiler.data_key(str(arg.children[0])))
    if storage in ("CONST", "VAR"):
        compiler.fail(node, f"GripLoad takes a persistent (PERS) loaddata: {arg.children[0]} is {storage}")
    value, where = compiler.expr(arg), compiler.where(node)

    def run(fr) -> None:
        load = rec(value(fr), "LOADDATA", where)
        cog, aom = load["COG"], load["AOM"]
        moments = [float(load[k]) for k in ("IX", "IY", "IZ")]
        values = {"mass": float(load["MASS"]), "cog": [float(cog[k]) for k in "XYZ"], "aom": vec(aom, QUAT_KEYS)}
        _record(fr, "gripload", {**values, "moments": moments}, where)

    return run


def speed(m, mm_s: float) -> float:
    """The TCP speed a move runs at under VelSet (its override, then its maximum)."""
    velset = m.state.velset
    if velset is None:
        return mm_s
    factor, top = velset
    return min(mm_s * factor, top)


def apply(m, settings: dict) -> None:
    """The recorded motion settings into a move's MoveEvent.settings."""
    recorded = m.state.settings
    if recorded is not None:
        settings.update(recorded)


BUILTINS = {
    "ACCSET": acc_set,
    "VELSET": vel_set,
    "SINGAREA": sing_area,
    "CONFJ": configuration_check("CONFJ"),
    "CONFL": configuration_check("CONFL"),
}
SPECIAL = {"GRIPLOAD": grip_load}  # compiled from its argument node (whether it names PERS data)
