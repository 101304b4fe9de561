"""KRL digital I/O: setting $OUT[n] and reading $IN[n], advance-run stops unless after CONTINUE (KSS 8)."""

from __future__ import annotations

from lark import Tree

from codegen.dialects.core.source import Src
from codegen.dialects.core.values import RunError

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
        raise RunError(f"{where}: {bank}[{value!r}]: the index must be 1..{IO_MAX}")
    return value


def output_store(compiler, target_node, value_node, node):
    """`$OUT[n] = value`: without CONTINUE the statement stops the advance run, so the output changes
    when the arm has finished its moves; after CONTINUE it runs ahead, while the arm still moves; None
    for any other assignment."""
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
    """`$IN[n]`: reading an input stops the advance run; its value is what the devices set (FALSE)."""
    if _bank(node) != "$IN":
        return None
    index, where = compiler.src(node.children[1]), compiler.where(node)
    stops = not compiler.take_continue()

    def read(fr, n):
        n = _number(n, where, "$IN")
        if stops:
            fr.m.arrive(where)
        return fr.m.input_signal(f"$IN[{n}]")

    return Src(f"{compiler.const(read)}(fr, {index})")


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
