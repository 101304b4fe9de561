"""KRL TRIGGER WHEN DISTANCE / PATH: an output switched at a point of the next motion, while the arm moves."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from lark import Tree

from codegen.dialects.core.machine import Frame, SignalEvent
from codegen.dialects.core.ramp import ramp_distance_at, ramp_time_at
from codegen.dialects.core.values import RunError

# KSS 8 programming manual for system integrators, "Path-related switching actions (TRIGGER)":
# - TRIGGER WHEN DISTANCE = 0 | 1 DELAY = t DO action [PRIO = p]: the action at the start (0) or the end (1)
#   point of the next motion, shifted by t ms (negative: earlier);
# - TRIGGER WHEN PATH = s [ONSTART] DELAY = t DO action: s mm from the end point of the next motion (from its
#   start with ONSTART; negative: before), shifted by t ms;
# - the trigger statement does not stop the advance run; it belongs to the next motion statement.
# What the interpreter models: the action sets an output ($OUT[n], or a SIGNAL name of outputs), recorded at
# the moment of the switching point in the program's clock (the move's start and end as the clock has them, a
# PATH point at the path speed), with the arm moving then; or it calls a subprogram (DO name(constants) PRIO = p)
# that runs at that moment beside the motion, as an interrupt routine does (codegen/dialects/krl/interrupts.py:
# it may not move the arm or wait; the outputs it sets are recorded at the switching point; the variables it
# sets change when the interpreter plans the motion, so a program that reads them in the advance run, before
# the switching point, sees them early: not modelled). The switching point of an approximated point (the middle
# of its approximation arc) is not modelled: the trace has no arcs, the point is the programmed one. A switching
# point outside its motion is refused. DO variable = value sets the variable at the switching point (as a
# subprogram's variables: it changes when the interpreter plans the motion).


@dataclass
class Trigger:
    kind: str  # "DISTANCE" or "PATH"
    at: float  # DISTANCE 0 / 1, or PATH mm
    onstart: bool
    delay_ms: float
    store: object  # [(output name, bit)], ("call", subprogram key, arguments) or ("assign", frame, assignment)
    value: object
    where: str


class TriggerStatements:
    """Compiler mixin: TRIGGER WHEN ... DO <output> = <value>."""

    def s_trigger_stmt(self, node):
        kind_token, at_node, onstart, delay_node, action, _prio = node.children
        kind = str(kind_token).upper()
        if kind not in ("DISTANCE", "PATH"):
            self.fail(kind_token, f"TRIGGER WHEN {kind_token}: expected DISTANCE or PATH")
        if onstart is not None and kind != "PATH":
            self.fail(onstart, "TRIGGER: ONSTART goes with PATH")
        inner = action.children[0]
        if inner.data == "assign":
            target, value_node = inner.children
            output = self.output_name(target)
            if output is None:  # a variable set at the switching point
                assign = self.s_assign(inner)

                def output(fr):
                    return ("assign", fr, assign)

                value = lambda fr: None  # noqa: E731
            else:
                value = self.expr(value_node)
        else:
            output, value = self.trigger_call(inner), (lambda fr: None)
        at, delay, where = (
            self.expr(at_node),
            (self.expr(delay_node) if delay_node is not None else None),
            self.where(node),
        )

        def run(fr):
            distance = float(at(fr))
            if kind == "DISTANCE" and distance not in (0.0, 1.0):
                raise RunError(f"{where}: TRIGGER WHEN DISTANCE takes 0 (the start point) or 1 (the end point)")
            pending = fr.m.state.triggers
            new = Trigger(
                kind, distance, onstart is not None, float(delay(fr)) if delay else 0.0, output(fr), value(fr), where
            )
            fr.m.state.triggers = (*pending, new)

        return run

    def trigger_call(self, node):
        """fr -> ("call", routine key, arguments) of DO name(constants): a DEF of the program."""
        name, args_node = node.children
        key = self.scope.routines.get(str(name).upper())
        if key is None or self.routine_signatures.get(key, ("",))[0] != "DEF":
            self.fail(node, f"TRIGGER ... DO {name}(): a DEF of the program's files is called")
        arg_nodes = args_node.children if args_node is not None else []
        modes = self.routine_signatures[key][1]
        if len(modes) != len(arg_nodes) or "OUT" in modes:
            self.fail(node, f"TRIGGER ... DO {name}(): {len(modes)} IN arguments (constants)")
        for arg in arg_nodes:
            inner = arg.children[0] if isinstance(arg, Tree) and arg.data == "neg" else arg
            if not (isinstance(inner, Tree) and inner.data in ("number", "true", "false", "enum", "string")):
                self.fail(arg, f"TRIGGER ... DO {name}(): the interpreter passes constants")
        args = [self.expr(a) for a in arg_nodes]
        return lambda fr: ("call", key, [a(fr) for a in args])

    def output_name(self, target):
        """fr -> [(output name, bit)] of an assignment target that is an output or a SIGNAL of outputs, or None."""
        if isinstance(target, Tree) and target.data == "index" and len(target.children) == 2:
            base = target.children[0]
            if isinstance(base, Tree) and base.data == "var" and str(base.children[0]).upper() == "$OUT":
                index = self.expr(target.children[1])
                return lambda fr: [(f"$OUT[{int(index(fr))}]", None)]
        if isinstance(target, Tree) and target.data == "var":
            group = self.scope.signals.get(str(target.children[0]).upper())
            if group is not None and group[0] == "$OUT":
                _bank, first, last, single = group
                names = [(f"$OUT[{n}]", None if single else bit) for bit, n in enumerate(range(first, last + 1))]
                return lambda fr: names
        return None


def fire(m, event, t0: float, speed_mm_s: float) -> None:
    """The triggers pending for this motion (event, from t0 to its end_time) switch their outputs."""
    triggers, m.state.triggers = m.state.triggers, ()
    t1 = event.end_time
    accel = event.settings.get("acc_cp") if event.kind == "linear" else None  # a LIN's ramps ($ACC.CP, m/s2)
    accel = None if accel is None else accel * 1000.0
    start = m.trace.moves[-2].tcp2base if len(m.trace.moves) > 1 else None
    end = event.tcp2base
    length = float(np.linalg.norm(end[:3, 3] - start[:3, 3])) if start is not None and end is not None else None
    for trigger in triggers:
        if trigger.kind == "DISTANCE":
            t = t0 if trigger.at == 0.0 else t1
        else:
            if length is None or not speed_mm_s:
                raise RunError(
                    f"{trigger.where}: TRIGGER WHEN PATH: the motion's path is not known here (a PTP "
                    "to axis values, or the first motion)"
                )
            mm = trigger.at if trigger.onstart else length + trigger.at
            if not -1e-6 <= mm <= length + 1e-6:
                raise RunError(
                    f"{trigger.where}: TRIGGER WHEN PATH = {trigger.at:g}: the switching point lies "
                    "outside its motion (not modelled)"
                )
            t = t0 + ramp_time_at(mm, length, speed_mm_s, accel)
        t += trigger.delay_ms / 1000.0
        if t < t0 - 1e-9:
            raise RunError(f"{trigger.where}: TRIGGER: the switching point lies before its motion (not modelled)")
        pose = _pose_at(start, end, t0, t1, t, speed_mm_s, accel)
        if isinstance(trigger.store, tuple) and trigger.store[0] == "assign":
            _assign(m, trigger, t)
            continue
        if isinstance(trigger.store, tuple):
            _call(m, trigger, t)
            continue
        line = int(trigger.where.split(":")[1]) if trigger.where.count(":") >= 2 else 0
        for name, bit in trigger.store:
            value = trigger.value if bit is None else bool((int(trigger.value) >> bit) & 1)
            if not isinstance(value, bool):
                raise RunError(f"{trigger.where}: {name} takes TRUE or FALSE")
            m.signals[name] = value
            m.trace.outputs.append(SignalEvent(name, value, line, t, t < t1, len(m.trace.moves), pose))


def _pose_at(start, end, t0: float, t1: float, t: float, speed_mm_s: float = 0.0, accel: float | None = None):
    """The TCP at t on a straight move from t0 to t1 (its ramps, where the move has an acceleration)."""
    if end is None:
        return None
    if start is None or t >= t1 or t1 <= t0:
        return end if t >= t1 else start
    length = float(np.linalg.norm(end[:3, 3] - start[:3, 3]))
    if accel and speed_mm_s and length > 0.0:
        s = ramp_distance_at(t - t0, length, speed_mm_s, accel) / length
    else:
        s = max(0.0, (t - t0) / (t1 - t0))
    pose = end.copy()
    pose[:3, 3] = start[:3, 3] + s * (end[:3, 3] - start[:3, 3])
    return pose


def _assign(m, trigger: Trigger, t: float) -> None:
    """DO variable = value: the assignment at the switching point t, in the frame of the routine that stated the
    trigger (its value is evaluated then, assumed)."""
    _kind, frame, assign = trigger.store
    saved = m.clock
    m.clock = max(saved, t)
    try:
        assign(frame)
    finally:
        m.clock = saved


def _call(m, trigger: Trigger, t: float) -> None:
    """The trigger's subprogram at the switching point t: the clock stands there while it runs (its outputs are
    recorded then); it runs in the main run (an advance-run stop in it waits for nothing); it may not move the arm
    or wait."""
    _kind, key, args = trigger.store
    label = f"the TRIGGER's subprogram ({trigger.where})"

    def no_move(event, *a, **k):
        raise RunError(f"{m.program.name}:{event.line}: a motion in {label}: not modelled")

    def no_wait(*a, **k):
        raise RunError(f"{trigger.where}: a wait in {label}: not modelled")

    saved = m.clock
    m.clock = max(saved, t)
    m.move, m.arrive, m.elapse, m.wait_for = no_move, (lambda where: None), no_wait, no_wait
    try:
        m.program.compiler.call_routine(Frame(m, m.globals, m.global_types), key, list(args), {}, trigger.where)
    finally:
        for attr in ("move", "arrive", "elapse", "wait_for"):
            del m.__dict__[attr]
        m.clock = saved
