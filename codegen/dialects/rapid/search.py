"""RAPID SearchL: a linear move that watches a digital input and stores the TCP where it changed."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from lark import Tree

from codegen.dialects.core.machine import MoveEvent
from codegen.dialects.core.values import RunError
from codegen.dialects.rapid import errors, motionset
from codegen.dialects.rapid.arguments import split_args
from codegen.dialects.rapid.motion import (
    move_event,
    no_motion_in_trap,
    robtarget_from,
    solve_event,
    speed_of,
    target_pose,
    wobj_matrix,
)
from codegen.dialects.rapid.types import vec

# SearchL [\Stop] | [\PStop] | [\SStop] | [\Sup] Signal [\Flanks] | [\PosFlank] | [\NegFlank] SearchPoint ToPoint
# Speed Tool [\WObj] (ABB, "Technical reference manual - RAPID Instructions, Functions and Data types", SearchL,
# as recalled: no copy of the manual's text was readable; real programs confirm \SStop, \Flanks and \NegFlank
# as accepted syntax). Assumed, as recalled:
# - the TCP moves linearly to ToPoint (a stop point) while the controller watches the digital input; the
#   search point is the TCP, in the Tool and work object given, at the moment the input changed: here the
#   first controller cycle that sees the change (targets/abb.toml signal_cycle_s);
# - no flank switch: the rising edge (0 to 1); \PosFlank the rising, \NegFlank the falling edge, \Flanks both;
# - \Stop, \PStop, \SStop: the arm stops at the first hit (its stopping distance is not modelled: it stops at
#   that cycle's pose, where the search point is); without a stop switch, or with \Sup, it goes on to ToPoint
#   and the search point is the first hit; \Sup with more than one hit is ERR_WHLSEARCH (the arm at ToPoint);
# - no hit before ToPoint: ERR_WHLSEARCH, the arm at ToPoint; the input already at the value the flank goes to
#   when the search starts (\PosFlank: 1, \NegFlank: 0; none with \Flanks): ERR_SIGSUPSEARCH, the arm does not
#   move. Both are RAPID errors: the routine's ERROR handler takes them, else the program stops.
# Not modelled and refused: \HighLevel, \LowLevel (their availability in RW6 is not confirmed), \ID, \T, \Corr,
# \TLoad. Without a device that switches the input with the arm's motion the input cannot change during the
# move: the search finds nothing (ERR_WHLSEARCH).
STOPS = ("STOP", "PSTOP", "SSTOP", "SUP")
FLANKS = {"POSFLANK": "rising", "NEGFLANK": "falling", "FLANKS": "both"}


def search_l(compiler, node, args_node) -> Callable:
    allowed = {*STOPS, *FLANKS, "WOBJ", "V"}
    refusal = "SearchL \\{arg} is not supported here"
    positional, named = split_args(compiler, node, args_node, allowed, refusal)
    if len(positional) != 5:
        compiler.fail(
            node, f"SearchL takes Signal, SearchPoint, ToPoint, Speed and Tool ({len(positional)} arguments given)"
        )
    stops = [k for k in STOPS if k in named]
    flanks = [k for k in FLANKS if k in named]
    for group, what in ((stops, "\\Stop, \\PStop, \\SStop and \\Sup"), (flanks, "\\Flanks, \\PosFlank and \\NegFlank")):
        if len(group) > 1:
            compiler.fail(node, f"SearchL: {what} exclude each other")
        if group and named[group[0]] is not None:
            compiler.fail(node, f"SearchL: \\{group[0].title()} is a switch (no value)")
    for key in ("WOBJ", "V"):
        if key in named and named[key] is None:
            compiler.fail(node, f"SearchL: \\{key.title()} needs a value (\\{key.title()}:=...)")
    signal_node, point_node, to_node, speed_node, tool_node = positional
    if not (isinstance(signal_node, Tree) and signal_node.data == "var"):
        compiler.fail(node, "SearchL: the signal is a name of the I/O configuration")
    if not (isinstance(point_node, Tree) and point_node.data in ("var", "index", "field")):
        compiler.fail(node, "SearchL: the search point is a robtarget variable (it is written)")
    signal = str(signal_node.children[0])
    store = compiler.lvalue(point_node)
    to, speed, tool = (compiler.expr(n) for n in (to_node, speed_node, tool_node))
    wobj = compiler.expr(named["WOBJ"]) if "WOBJ" in named else None
    override = compiler.expr(named["V"]) if "V" in named else None
    stop = stops[0] if stops else None
    edge = FLANKS[flanks[0]] if flanks else "rising"
    where = compiler.where(node)

    def run(fr):
        m = fr.m
        no_motion_in_trap(fr, where, "SearchL")
        if signal.upper() in m.globals:
            raise RunError(f"{where}: SearchL: {signal} is program data, not a digital input")
        wobj_value = wobj(fr) if wobj is not None else None
        speed_value = speed(fr)
        mm_s = speed_of(speed_value, {"V": override(fr)} if override is not None else {}, where)
        target_m, target = target_pose(compiler, to(fr), wobj_value, where)
        watching = m.watching if m.watching is not None and m.watching.handles(signal) else None
        t0 = max(m.clock, m.arm_until)  # the search starts where the motion before it ends
        before = watching.value(signal, t0) if watching is not None else bool(m.input_signal(signal))
        if edge != "both" and before == (edge == "rising"):
            raise errors.RapidError(
                errors.ERROR_NUMBERS["ERR_SIGSUPSEARCH"],
                f"{where}: SearchL: {signal} is already {int(before)} when the search starts",
            )
        args = [target, speed_value, "FINE", tool(fr)]
        event = move_event(fr, "linear", target_m, target, args, (mm_s, False), where, solve=False, wobj=wobj_value)
        m.move(event, motionset.speed(m, mm_s), runs_ahead=True)
        hits = _hits(m, watching, signal, edge, before, t0, event.end_time, stop is not None and stop != "SUP")
        if hits and stop is not None and stop != "SUP":
            _stop_at(m, event, hits[0][1], hits[0][0])
        solve_event(fr, "linear", event, target, where)
        m.arrive(where)  # a stop point: the program goes on once the arm stands
        if not hits:
            raise errors.RapidError(
                errors.ERROR_NUMBERS["ERR_WHLSEARCH"], f"{where}: SearchL: no {edge} edge of {signal} before ToPoint"
            )
        if stop == "SUP" and len(hits) > 1:
            raise errors.RapidError(
                errors.ERROR_NUMBERS["ERR_WHLSEARCH"], f"{where}: SearchL \\Sup: {signal} changed {len(hits)} times"
            )
        base2wobj = np.linalg.inv(wobj_matrix(compiler, wobj_value, where))
        conf = vec(target["ROBCONF"], ("CF1", "CF4", "CF6", "CFX"))  # a linear move keeps its configuration
        store(fr, robtarget_from(base2wobj @ hits[0][1], conf, where))

    return run


def _hits(m, watching, signal: str, edge: str, before: bool, t0: float, t1: float, first: bool) -> list:
    """(time, tcp2base) of each cycle in (t0, t1] where the input changed the way the search looks for: the
    input's history is evaluated cycle by cycle, no further than the first hit when the arm stops there."""
    if watching is None:
        return []
    cycle = watching.cycle
    hits, last = [], before
    for k in range(math.floor(t0 / cycle + 1e-9) + 1, math.floor(t1 / cycle + 1e-9) + 1):
        value = watching.value(signal, k * cycle)
        if value == last:
            continue
        last = value
        if edge == "both" or value == (edge == "rising"):
            pose = watching.pose_at(k * cycle)[0]
            if pose is None:  # the path is not known (cannot happen on a linear move from a known pose)
                raise RunError(f"SearchL: the arm's pose at {k * cycle:.3f} s is not known")
            hits.append((k * cycle, pose))
            if first:
                break
    return hits


def _stop_at(m, event: MoveEvent, pose: np.ndarray, t: float) -> None:
    """The search move cut short: the arm stops at the hit's pose at its cycle (no stopping distance)."""
    m.cut_move(event, t, pose)
