"""KRL digital I/O: setting $OUT[n] and reading $IN[n], advance-run stops unless after CONTINUE (KSS 8)."""

from __future__ import annotations

from lark import Tree

from codegen.dialects.core.source import Src
from codegen.dialects.core.values import F32, RunError
from codegen.dialects.krl.builtins import shown

IO_MAX = 4096  # $IN[1..4096], $OUT[1..4096] (kuka.toml signals)


def _bank(node) -> str | None:
    """'$IN' or '$OUT' when node is an element of one, else None."""
    if isinstance(node, Tree) and node.data == "index" and len(node.children) == 2:
        base = node.children[0]
        if isinstance(base, Tree) and base.data == "var" and str(base.children[0]).upper() in ("$IN", "$OUT"):
            return str(base.children[0]).upper()
    return None


def _number(value, where: str, bank: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= IO_MAX:
        raise RunError(f"{where}: {bank}[{shown(value)}]: the index must be 1..{IO_MAX}")
    return value


def output_store(compiler, target_node, value_node, node):
    """`$OUT[n] = value`: without CONTINUE the statement stops the advance run, so the output changes
    when the arm has finished its moves; after CONTINUE it runs ahead, while the arm still moves; None
    for any other assignment. An input is the devices': the program cannot set it."""
    if _bank(target_node) == "$IN":
        compiler.fail(node, "$IN[n] is an input: the devices set it, the program cannot")
    if _bank(target_node) != "$OUT":
        return None
    index, value, where = compiler.expr(target_node.children[1]), compiler.expr(value_node), compiler.where(node)
    stops = not compiler.take_continue()

    def store(fr):
        n, v = _number(index(fr), where, "$OUT"), value(fr)
        if not isinstance(v, bool):
            raise RunError(f"{where}: $OUT[{n}] takes TRUE or FALSE")
        if stops:
            fr.m.arrive(where)
        fr.m.set_output(f"$OUT[{n}]", v, where)

    return store


def input_read(compiler, node) -> Src | None:
    """`$IN[n]`: reading an input stops the advance run; its value is what the devices set (FALSE). `$OUT[n]`:
    the output as the program last set it (FALSE before), read without stopping the advance run (assumed)."""
    bank = _bank(node)
    if bank == "$OUT":
        index, where = compiler.src(node.children[1]), compiler.where(node)

        def read_output(fr, n):
            return fr.m.signals.get(f"$OUT[{_number(n, where, '$OUT')}]", False)

        return Src(f"{compiler.const(read_output)}(fr, {index})")
    if bank != "$IN":
        return None
    index, where = compiler.src(node.children[1]), compiler.where(node)
    stops = not compiler.take_continue()

    def read(fr, n):
        n = _number(n, where, "$IN")
        if stops:
            fr.m.arrive(where)
        return fr.m.input_signal(f"$IN[{n}]")

    return Src(f"{compiler.const(read)}(fr, {index})")


def _pulsed(compiler, node, first):
    """The output number of PULSE's first argument: $OUT[n], or a SIGNAL name of one output ($OUT[n])."""
    if _bank(first) == "$OUT":
        return compiler.expr(first.children[1])
    is_name = isinstance(first, Tree) and first.data == "var"
    group = compiler._group(first.children[0]) if is_name else None
    if group is not None:
        bank, a, b, _single = group
        if bank == "$OUT" and a == b:
            return lambda fr: a
        what = f"{bank}[{a}]" if a == b else f"{b - a + 1} signals {bank}[{a}] TO {bank}[{b}]"
        compiler.fail(node, f"PULSE: {first.children[0]} is {what}; a pulse is of one output ($OUT[n])")
    compiler.fail(node, "PULSE($OUT[n], state, seconds): the interpreter models a pulse of one output")


def pulse(compiler, node):
    """PULSE($OUT[n], state, seconds): the output takes state for that time, then the other value (KSS 8
    programming manual, PULSE: like an output set it stops the advance run unless after CONTINUE; the pulse
    runs on while the program goes on, recorded as two output events, the second at its end)."""
    args = node.children[1].children if node.children[1] is not None else []
    if len(args) != 3 or any(a is None for a in args):
        compiler.fail(node, "PULSE($OUT[n], state, seconds): the interpreter models a pulse of one output")
    index, state, seconds = _pulsed(compiler, node, args[0]), compiler.expr(args[1]), compiler.expr(args[2])
    where, stops = compiler.where(node), not compiler.take_continue()

    def run(fr):
        n, value, t = _number(index(fr), where, "$OUT"), state(fr), seconds(fr)
        if not isinstance(value, bool):
            raise RunError(f"{where}: PULSE: the state is TRUE or FALSE")
        number = not isinstance(t, bool) and isinstance(t, int | float | F32)
        if not number or not 0.012 <= float(t) <= 2**31 / 1000:
            raise RunError(f"{where}: PULSE: the time is a number of seconds (at least 0.012 s)")
        if stops:
            fr.m.arrive(where)
        name = f"$OUT[{n}]"
        fr.m.set_output(name, value, where)
        end = fr.m.trace.outputs[-1]
        later = fr.m.clock + float(t)
        back = type(end)(name, not value, end.line, later, end.moving, end.after_moves, end.tcp2base)
        fr.m.trace.outputs.append(back)
        fr.m.signals[name] = not value  # the pulse's end: what the program reads after it (assumed)

    return run


class ContinueStatement:
    """Compiler mixin. CONTINUE: the next statement does not stop the advance run (KSS 8: an output set
    or an input read runs ahead of the motion); KRL has no loop-continue. The flag is taken by the first
    I/O access compiled after it (output_store, input_read)."""

    continued = False  # compiling the statement after a CONTINUE

    def s_continue_stmt(self, node):
        self.continued = True
        return self.s_pass_stmt(node)

    def stmt(self, node):
        compiled = super().stmt(node)
        if node.data != "continue_stmt":
            self.continued = False  # CONTINUE covers the next statement only
        return compiled

    def take_continue(self) -> bool:
        """Whether the I/O access being compiled follows a CONTINUE (and use the CONTINUE up)."""
        continued, self.continued = self.continued, False
        return continued
