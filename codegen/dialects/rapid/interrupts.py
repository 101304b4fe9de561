"""RAPID interrupts: TRAP routines, CONNECT, ISignalDI and IDelete, run through the core's watchers."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from lark import Tree

from codegen.dialects.core.machine import Frame
from codegen.dialects.core.values import RunError, f32
from codegen.dialects.rapid import errors
from codegen.dialects.rapid.arguments import split_args
from codegen.dialects.rapid.types import num

# Sources: ABB, "Technical reference manual - RAPID Instructions, Functions and Data types", CONNECT,
# ISignalDI, IDelete and the data type intnum, as recalled (no copy of the manual's text could be read, so
# every rule below is assumed):
# - CONNECT Interrupt WITH Trap_routine: the intnum variable gets the identity of a new interrupt, handled
#   by the TRAP routine; the variable must be module data (not declared in a routine); connecting a variable
#   that is already connected is an error (ERR_ALRDYCNT on the controller: refused here);
# - ISignalDI [\Single] | [\SingleSafe] Signal, TriggValue, Interrupt: the interrupt comes when the digital
#   input changes to TriggValue: 1 (high) its rising edge, 0 (low) its falling edge, 2 (edge) both; edge
#   triggered: a signal that already has the value when the interrupt is ordered gives none; \Single: the
#   interrupt comes once, then it is off; one interrupt variable is ordered once until it is deleted;
# - IDelete Interrupt: the interrupt is cancelled and its TRAP disconnected (the usual "IDelete, CONNECT"
#   at a program's start: deleting a variable that holds no interrupt is allowed);
# - a TRAP routine is never called: it runs when its interrupt comes, between two instructions of the
#   program, while the arm goes on moving.
# Here (codegen/dialects/core/watch.py): the controller sees the input once per cycle (targets/abb.toml
# signal_cycle_s); the TRAP runs at the first cycle after the edge, with the clock there, so CRobT in it
# returns the TCP at that cycle and DInput the input's new value. The interrupt's latency and the TRAP's own
# start-up time are not modelled (the facts say CRobT in a real TRAP returns the pose a little later: none
# was found in figures). A TRAP may not move the arm or wait here. Without a device that switches inputs with
# the arm's motion (Machine.watching None) no interrupt comes.
EDGES = {0: "falling", 1: "rising", 2: "both"}


@dataclass
class Interrupts:
    """One run's interrupts: the numbers CONNECT gave out, the TRAP of each, the ordered ones' watchers."""

    issued: int = 0
    connected: dict[int, str] = field(default_factory=dict)  # number -> TRAP's key
    ordered: dict[int, object] = field(default_factory=dict)  # number -> its Watcher (None without watching)


def state(machine) -> Interrupts:
    found = machine.state.interrupts
    if found is None:  # made in the run: the run's own
        found = machine.state.interrupts = Interrupts()
    return found


def _number(value, where: str, name: str) -> int:
    number = num(value, where)
    if number != int(number) or number < 0:
        raise RunError(f"{where}: {name} holds {number:g}, not an interrupt number")
    return int(number)


def _intnum_variable(compiler, node, arg, what: str) -> str:
    """The intnum variable an instruction names: a module VAR (a name; routine data is refused)."""
    if not (isinstance(arg, Tree) and arg.data == "var"):
        compiler.fail(node, f"{what}: the interrupt is an intnum variable's name")
    key = str(arg.children[0]).upper()
    if compiler.local_types is not None and key in compiler.local_types:
        compiler.fail(node, f"{what}: {arg.children[0]} is routine data: an interrupt variable is module data")
    return key


def _check_intnum(fr, compiler, key: str, name: str, where: str, what: str) -> None:
    kind = fr.m.global_types.get(key)
    if key not in fr.m.globals:
        raise RunError(f"{where}: {what}: undefined variable {name}")
    if kind != "INTNUM" or compiler.storage.get(key) != "VAR":
        shown = f"{compiler.storage.get(key, '').lower()} {str(kind).lower() if isinstance(kind, str) else 'array'}"
        raise RunError(f"{where}: {what}: {name} is a {shown}, not a VAR intnum")


def connect(compiler, node) -> Callable:
    """CONNECT intno WITH trap."""
    target, trap_name = node.children
    key = _intnum_variable(compiler, node, target, "CONNECT")
    trap = str(trap_name).upper()
    if trap not in compiler.trap_names:
        kind = "a PROC or FUNC, not a TRAP" if trap in (compiler.user_routines or ()) else "no TRAP routine here"
        compiler.fail(node, f"CONNECT ... WITH {trap_name}: {kind}")
    name, where = str(target.children[0]), compiler.where(node)
    read, store = compiler.expr(target), compiler.lvalue(target)

    def run(fr):
        _check_intnum(fr, compiler, key, name, where, "CONNECT")
        interrupts = state(fr.m)
        current = _number(read(fr), where, name)
        if current in interrupts.connected:
            other = compiler.traps[interrupts.connected[current]].name
            raise RunError(f"{where}: CONNECT: {name} is already connected to TRAP {other} (IDelete it first)")
        interrupts.issued += 1
        interrupts.connected[interrupts.issued] = trap
        store(fr, f32(interrupts.issued))

    return run


def _signal_name(compiler, node, arg) -> str:
    if not (isinstance(arg, Tree) and arg.data == "var"):
        compiler.fail(node, f"{node.children[0]}: the signal is a name of the I/O configuration")
    return str(arg.children[0])


def i_signal_di(compiler, node, args_node) -> Callable:
    """ISignalDI [\\Single] | [\\SingleSafe] Signal, TriggValue, Interrupt."""
    refusal = "ISignalDI \\{arg} is not supported here (\\Single, \\SingleSafe)"
    positional, named = split_args(compiler, node, args_node, {"SINGLE", "SINGLESAFE"}, refusal)
    if len(positional) != 3:
        compiler.fail(node, f"ISignalDI takes a signal, a trigger value and an interrupt ({len(positional)} given)")
    if len(named) > 1:
        compiler.fail(node, "ISignalDI: \\Single and \\SingleSafe exclude each other")
    if any(v is not None for v in named.values()):
        compiler.fail(node, "ISignalDI: \\Single and \\SingleSafe are switches (no value)")
    signal = _signal_name(compiler, node, positional[0])
    trigger = compiler.expr(positional[1])
    key = _intnum_variable(compiler, node, positional[2], "ISignalDI")
    name, read = str(positional[2].children[0]), compiler.expr(positional[2])
    single, where = bool(named), compiler.where(node)

    def run(fr):
        m = fr.m
        _check_intnum(fr, compiler, key, name, where, "ISignalDI")
        if signal.upper() in m.globals:
            raise RunError(f"{where}: ISignalDI: {signal} is program data, not a digital input")
        value = num(trigger(fr), where)
        if value not in EDGES:
            raise RunError(f"{where}: ISignalDI: trigger value {value:g}: 0 (falling), 1 (rising) or 2 (both edges)")
        interrupts = state(m)
        number = _number(read(fr), where, name)
        trap = interrupts.connected.get(number)
        if trap is None:
            raise RunError(f"{where}: ISignalDI: {name} is not connected to a TRAP (CONNECT it first)")
        if number in interrupts.ordered:
            raise RunError(f"{where}: ISignalDI: {name} is already ordered (IDelete it before ordering it again)")
        watcher = None
        if m.watching is not None:
            if not m.watching.handles(signal):
                raise RunError(f"{where}: ISignalDI: no device here switches the input {signal} while the arm moves")
            holder = {}
            handler = _handler(compiler, m, trap, single, where, holder)
            watcher = holder["watcher"] = m.watching.watch(signal, EDGES[int(value)], handler)
        interrupts.ordered[number] = watcher

    return run


def _handler(compiler, machine, trap: str, single: bool, where: str, holder: dict):
    """What runs at each edge: the TRAP (once with \\Single: then the interrupt is off; holder["watcher"] is
    the handler's own watcher)."""

    def handler(t, _tcp2base):
        if single:
            machine.watching.unwatch(holder["watcher"])  # off from this cycle: later edges never come
        run_trap(compiler, machine, trap, where)

    return handler


def run_trap(compiler, machine, trap: str, where: str) -> None:
    """The TRAP routine, at the clock the edge was seen; an error it does not handle itself stops the program
    (no routine of the interrupted program may take it)."""
    routine = compiler.traps[trap]
    machine.state.trap = routine.name
    try:
        compiler.entry(routine)(Frame(machine, machine.globals, machine.global_types), [], {}, where)
    except errors.RapidError as error:
        error.fatal = True
        raise
    finally:
        machine.state.trap = None


def i_delete(compiler, node, args_node) -> Callable:
    """IDelete Interrupt: the edges up to now still run their TRAP, later ones never; the variable is free."""
    positional, _named = split_args(compiler, node, args_node, set())
    if len(positional) != 1:
        compiler.fail(node, "IDelete takes one interrupt variable")
    key = _intnum_variable(compiler, node, positional[0], "IDelete")
    name, where = str(positional[0].children[0]), compiler.where(node)
    read, store = compiler.expr(positional[0]), compiler.lvalue(positional[0])

    def run(fr):
        _check_intnum(fr, compiler, key, name, where, "IDelete")
        interrupts = state(fr.m)
        number = _number(read(fr), where, name)
        watcher = interrupts.ordered.pop(number, None)
        if watcher is not None:
            fr.m.watching.unwatch(watcher)
        interrupts.connected.pop(number, None)
        store(fr, f32(0))

    return run


SPECIAL = {"ISIGNALDI": i_signal_di, "IDELETE": i_delete}
