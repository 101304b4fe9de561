"""KRL interrupts: INTERRUPT DECL ... WHEN ... DO and INTERRUPT ON / OFF / ENABLE / DISABLE (KSS 8)."""

from __future__ import annotations

from dataclasses import dataclass

from lark import Token, Tree

from codegen.dialects import posemath
from codegen.dialects.core.machine import Frame
from codegen.dialects.core.values import Record, RunError, f32
from codegen.dialects.krl.builtins import UNINIT
from codegen.dialects.krl.io import IO_MAX
from codegen.dialects.krl.position import motion_base
from codegen.poses import invert

# KSS 8 programming manual, interrupt programming: priorities 1..128 (KUKA's own routines use 3, 19
# and 40..80), at most 32 interrupts declared and 16 switched on at a time. Interrupt 3 is the
# template's: WHEN $STOPMESS (a stop message, e.g. an EMERGENCY STOP) DO IR_STOPM(), KUKA's routine in
# R1/System that stops the arm and keeps the position for the restart.
PRIORITIES = range(1, 129)
MAX_DECLARED = 32
MAX_ON = 16
SYSTEM_HANDLERS = frozenset({"IR_STOPM"})
ACTIONS = frozenset({"ON", "OFF", "ENABLE", "DISABLE"})

# What the interpreter models of an interrupt that fires (no KSS 8 manual text was reachable, so each
# point is marked):
# - the event is edge-triggered: the routine is called when the condition becomes TRUE, not while it is
#   TRUE; TRUE already at INTERRUPT ON does not fire (secondary sources: KUKA training material, Euclid
#   Labs; the manual's wording recalled);
# - only a condition on one digital input is seen changing: $IN[k], NOT $IN[k], $IN[k] == TRUE / FALSE
#   (or <>) with a constant k, through the core's watchers (codegen/dialects/core/watch.py) once per
#   controller cycle (targets/kuka.toml signal_cycle_s: 12 ms, the interpolation cycle, assumed); any
#   other condition ($STOPMESS, a variable) never becomes TRUE here; a condition that mixes an input with
#   anything else is refused (not modelled);
# - interrupts that fire in the same cycle run by priority, the lower number first (manual, recalled);
# - $POS_INT: the TCP's cartesian pose when the interrupt fired, in the $BASE and $TOOL of the motion
#   under way (recalled, not confirmed); S, T of it are not modelled (no value);
# - INTERRUPT ON / OFF / ENABLE / DISABLE do not stop the advance run (assumed: not in the list of
#   statements known here to stop it): run while the arm still executes earlier moves, they act at that
#   moment, so an INTERRUPT OFF after a motion without an advance-run stop (WAIT SEC 0) before it switches
#   the interrupt off before the arm gets there and its edges are lost;
# - INTERRUPT DISABLE: an event is detected and saved, its routine runs at ENABLE (secondary: KUKA training
#   material); one event is kept per interrupt (assumed), with its $POS_INT;
# - the routine runs while the arm moves on (no BRAKE modelled): it may not move the arm, wait or stop the
#   advance run while the arm moves (refused: not modelled); it must be a DEF (assumed: a function's value
#   would go nowhere) and its arguments are constants (when a variable argument is evaluated, at the
#   declaration or at the event, is not confirmed: refused).


@dataclass
class Interrupt:
    number: int
    handler: str
    args: list
    signal: str | None  # "$IN[k]": the watched input; None: a condition never seen to become TRUE here
    edge: str | None  # "rising" / "falling": the input's change that makes the condition TRUE
    where: str
    state: str = "OFF"  # "OFF", "ON", "DISABLED" (on, its events saved)
    watcher: object = None
    pending: object = None  # the $POS_INT of an event saved while disabled (False: none)


def routine_signatures(tree) -> dict[str, tuple[str, list[str]]]:
    """Each routine of a .src by upper-case name: ("DEF" or "DEFFCT", its parameters' modes IN / OUT)."""
    out = {}
    for item in tree.children:
        if not isinstance(item, Tree) or item.data not in ("def_routine", "def_function"):
            continue
        function = item.data == "def_function"
        name, params = (item.children[1], item.children[2]) if function else (item.children[0], item.children[1])
        modes = []
        for param in params.children if params is not None else []:
            mode = param.children[2]
            modes.append(str(mode).upper() if mode is not None else "IN")
        out[str(name).upper()] = ("DEFFCT" if function else "DEF", modes)
    return out


def _input_number(node) -> int | None:
    """k of $IN[k] (-1: a computed index), None when node is not an element of $IN."""
    if isinstance(node, Tree) and node.data == "index" and len(node.children) == 2:
        base, index = node.children
        if isinstance(base, Tree) and base.data == "var" and str(base.children[0]).upper() == "$IN":
            if isinstance(index, Tree) and index.data == "number" and str(index.children[0]).isdigit():
                return int(str(index.children[0]))
            return -1
    return None


def _mentions_input(compiler, node) -> bool:
    groups = compiler.scope.signals
    for sub in node.iter_subtrees() if isinstance(node, Tree) else ():
        if _input_number(sub) is not None:
            return True
        if sub.data == "var" and groups.get(str(sub.children[0]).upper(), ("",))[0] == "$IN":
            return True
    return False


def _signal_as_input(compiler, node):
    """A SIGNAL name of one input as the element $IN[k] it names (any other node as it is)."""
    if isinstance(node, Tree) and node.data == "var":
        group = compiler.scope.signals.get(str(node.children[0]).upper())
        if group is not None and group[0] == "$IN" and group[3]:
            return Tree("index", [Tree("var", [Token("NAME", "$IN")]), Tree("number", [Token("INT", str(group[1]))])])
    if isinstance(node, Tree):
        return Tree(node.data, [_signal_as_input(compiler, c) for c in node.children], node.meta)
    return node


def watched_input(compiler, node) -> tuple[str | None, str | None]:
    """("$IN[k]", "rising" | "falling") for a condition on one input (or a SIGNAL name of one), (None, None) for
    one that mentions no input (never seen to become TRUE here); a compile error for any other on inputs."""
    node = _signal_as_input(compiler, node)
    number, rising = _input_number(node), True
    if number is None and isinstance(node, Tree) and node.data == "not_":
        number, rising = _input_number(node.children[1]), False
    if number is None and isinstance(node, Tree) and node.data == "compare":
        left, op, right = node.children
        for side, other in ((left, right), (right, left)):
            truth = isinstance(other, Tree) and other.data in ("true", "false")
            if _input_number(side) is not None and truth and str(op) in ("==", "<>"):
                number, rising = _input_number(side), (other.data == "true") == (str(op) == "==")
    if number is None or number < 0:
        if number is not None or _mentions_input(compiler, node):
            compiler.fail(
                node,
                "INTERRUPT DECL: the interpreter models a condition on one input: $IN[k], NOT $IN[k] or "
                "$IN[k] == TRUE / FALSE with a constant k",
            )
        return None, None
    if not 1 <= number <= IO_MAX:
        compiler.fail(node, f"INTERRUPT DECL: $IN[k] with a constant k in 1..{IO_MAX}")
    return f"$IN[{number}]", "rising" if rising else "falling"


def _constant_argument(compiler, node):
    """The value of a constant argument of an interrupt routine (a number, TRUE / FALSE, an enum, a string)."""
    inner = node.children[0] if isinstance(node, Tree) and node.data == "neg" else node
    if not (isinstance(inner, Tree) and inner.data in ("number", "true", "false", "enum", "string")):
        compiler.fail(
            node,
            "INTERRUPT DECL: the interpreter passes constants to an interrupt routine (when a variable is "
            "read, at the declaration or when the interrupt fires, is not confirmed)",
        )
    return compiler.expr(node)


class InterruptStatements:
    """Compiler mixin: what the controller refuses when the program runs (a priority out of range, a
    handler that is neither the program's nor KUKA's, too many interrupts, switching on one never declared)
    and, where a device switches an input while the arm moves (Machine.watching), the interrupts on it."""

    routine_signatures: dict | None = None

    def s_interrupt_decl(self, node):
        _global, priority, condition, handler, args_node = node.children
        number, name, where = int(str(priority)), str(handler).upper(), self.where(node)
        if number not in PRIORITIES:
            self.fail(node, f"INTERRUPT DECL {number}: the priority must be in 1..128")
        if self.user_routines is not None and name not in self.user_routines and name not in SYSTEM_HANDLERS:
            self.fail(node, f"INTERRUPT DECL {number}: no routine {handler} to call")
        arg_nodes = args_node.children if args_node is not None else []
        args = [_constant_argument(self, a) for a in arg_nodes]
        signature = (self.routine_signatures or {}).get(name)
        if name in SYSTEM_HANDLERS and arg_nodes:
            self.fail(node, f"INTERRUPT DECL {number}: {name} takes no arguments")
        if signature is not None:
            kind, modes = signature
            if kind != "DEF":
                self.fail(node, f"INTERRUPT DECL {number}: {name} is a function (DEFFCT): an interrupt calls a DEF")
            if len(modes) != len(args):
                self.fail(node, f"INTERRUPT DECL {number}: {name} takes {len(modes)} arguments, got {len(args)}")
            if "OUT" in modes:
                self.fail(node, f"INTERRUPT DECL {number}: {name} has an OUT parameter: it gets a constant here")
        signal, edge = watched_input(self, condition)

        def run(fr):
            declared = fr.m.state.interrupts
            if number not in declared and len(declared) >= MAX_DECLARED:
                raise RunError(f"{where}: more than {MAX_DECLARED} interrupts declared")
            fr.m.deliver()  # the old declaration's edges up to now
            old = declared.get(number)
            if old is not None and old.watcher is not None:
                fr.m.watching.unwatch(old.watcher)
            declared[number] = Interrupt(number, name, [a(fr) for a in args], signal, edge, where)

        return run

    def s_interrupt_stmt(self, node):
        action, priority = str(node.children[0]).upper(), node.children[1]
        number, where = (int(str(priority)) if priority is not None else None), self.where(node)
        if action not in ACTIONS:
            self.fail(node, f"INTERRUPT {action}: expected ON, OFF, ENABLE or DISABLE")

        def run(fr):
            declared = fr.m.state.interrupts
            fr.m.deliver()  # the edges up to now reach the interrupts as they were switched until now
            for n in [number] if number is not None else sorted(declared):
                if n not in declared:
                    raise RunError(f"{where}: INTERRUPT {action} {n}: interrupt {n} is not declared")
                it = declared[n]
                if action == "ON" and it.state == "OFF":
                    if sum(i.state != "OFF" for i in declared.values()) >= MAX_ON:
                        raise RunError(f"{where}: INTERRUPT ON {n}: more than {MAX_ON} interrupts on")
                    it.state, it.pending = "ON", None
                    _watch(fr.m, it)
                elif action == "OFF" and it.state != "OFF":
                    if it.watcher is not None:
                        fr.m.watching.unwatch(it.watcher)
                    it.state, it.watcher, it.pending = "OFF", None, None
                elif action == "DISABLE" and it.state == "ON":
                    it.state = "DISABLED"
                elif action == "ENABLE" and it.state == "DISABLED":
                    it.state = "ON"
                    if it.pending is not None:  # the event saved while disabled: its routine runs now
                        pending, it.pending = it.pending, None
                        _run(fr.m, it, pending)

        return run


def _watch(machine, it: Interrupt) -> None:
    """Watch the interrupt's input from now (nothing to watch without a device switching it in motion)."""
    watching = machine.watching
    if watching is None or it.signal is None:
        return
    it.watcher = watching.watch(it.signal, it.edge, lambda t, tcp2base: _fire(machine, it, t, tcp2base))
    it.watcher.krl_priority = it.number
    # the same cycle's events run in the watchers' order: the lower priority number first
    watching.watchers.sort(key=lambda w: getattr(w, "krl_priority", 0))


def _fire(machine, it: Interrupt, t: float, tcp2base) -> None:
    """The condition became TRUE at the cycle t (the machine's clock is t, the TCP there tcp2base)."""
    latched = _latched(machine, it, t, tcp2base)
    if it.state == "DISABLED":
        if it.pending is None:
            it.pending = latched
        return
    _run(machine, it, latched)  # on (an interrupt switched off is no longer watched)


def _latched(machine, it: Interrupt, t: float, tcp2base):
    """$POS_INT for an event at t: an E6POS in the motion's $BASE, or a text saying why it is not known."""
    if tcp2base is None:
        return f"the arm's pose when interrupt {it.number} fired is not known here (a PTP under way)"
    pose = invert(motion_base(machine, t)) @ tcp2base
    values = posemath.xyzabc_from_matrix(pose)
    fields = dict(zip(("X", "Y", "Z", "A", "B", "C"), (f32(v) for v in values), strict=True))
    return Record("E6POS", {**fields, "S": UNINIT, "T": UNINIT, **{f"E{i}": f32(0.0) for i in range(1, 7)}})


def _run(machine, it: Interrupt, latched) -> None:
    """Call the interrupt's routine now with $POS_INT latched; it may not move the arm, wait, or stop the
    advance run while the arm moves (the routine runs beside the motion, which goes on)."""
    if it.handler in SYSTEM_HANDLERS:
        raise RunError(f"{it.where}: interrupt {it.number} fired: KUKA's {it.handler} is not modelled here")
    label = f"the interrupt routine {it.handler} (interrupt {it.number})"

    def no_move(event, *args, **kwargs):
        raise RunError(f"{machine.program.name}:{event.line}: a motion in {label}: not modelled (no BRAKE here)")

    def no_wait(*args, **kwargs):
        where = next((a for a in args if isinstance(a, str)), "?")
        raise RunError(f"{where}: a wait in {label}: not modelled")

    real_arrive = machine.arrive

    def arrive(where):
        if machine.moving:
            raise RunError(f"{where}: an advance-run stop in {label} while the arm moves: not modelled")
        real_arrive(where)

    machine.state.sysvars["$POS_INT"] = latched
    machine.move, machine.arrive, machine.elapse, machine.wait_for = no_move, arrive, no_wait, no_wait
    try:
        frame = Frame(machine, machine.globals, machine.global_types)
        machine.program.compiler.call_routine(frame, it.handler, list(it.args), {}, it.where)
    finally:
        for attr in ("move", "arrive", "elapse", "wait_for"):
            del machine.__dict__[attr]


def pos_int(machine, where: str) -> Record:
    """$POS_INT as the program reads it: the pose latched by the last interrupt that fired."""
    value = machine.state.sysvars.get("$POS_INT")
    if value is None:
        raise RunError(f"{where}: $POS_INT has no value: no interrupt has fired (KRL: variable value invalid)")
    if isinstance(value, str):
        raise RunError(f"{where}: $POS_INT: {value}")
    return value
