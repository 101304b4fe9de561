"""KRL signal groups: SIGNAL name $IN[a] TO $IN[b] (or $OUT), read and written as one INT (KSS 8)."""

from __future__ import annotations

from lark import Tree

from codegen.dialects.core.source import Src
from codegen.dialects.core.values import RunError
from codegen.dialects.krl.io import IO_MAX

# KSS 8 programming manual for system integrators, signal declaration (SIGNAL), as quoted by KUKA
# integrators' write-ups: SIGNAL name $IN[a] TO $IN[b] (or $OUT) groups consecutive inputs or outputs
# into one INT; $IN[a] is the least significant bit; up to 32 signals: up to 31 give an unsigned value,
# 32 a signed one (two's complement); declared in a data list or a routine's declaration section.
# Reading a group of inputs stops the advance run, as reading $IN[n] does; writing a group of outputs
# sets each output once the arm stands (unless after CONTINUE).
MAX_BITS = 32


ANALOG = ("$ANIN", "$ANOUT")  # SIGNAL name $ANOUT[n] ($config.dat's channels): declared, refused where used


def _bank_index(node) -> tuple[str, int] | None:
    """('$IN' | '$OUT' | '$ANIN' | '$ANOUT', n) of a constant element $IN[n], else None."""
    if isinstance(node, Tree) and node.data == "index" and len(node.children) == 2:
        base, index = node.children
        bank = str(base.children[0]).upper() if isinstance(base, Tree) and base.data == "var" else None
        if bank in ("$IN", "$OUT", *ANALOG) and isinstance(index, Tree) and index.data == "number":
            return bank, int(str(index.children[0]))
    return None


class SignalGroups:
    """Compiler mixin: SIGNAL declarations and the names they declare in expressions and assignments: one
    input or output (SIGNAL name $IN[n]: a BOOL) or consecutive ones (SIGNAL name $IN[a] TO $IN[b]: an INT).
    A module's signals are its own; $config.dat's and a data list's GLOBAL SIGNAL are every module's (scope.signals)."""

    def s_signal_decl(self, node):
        name, first_node, last_node = node.children
        first = _bank_index(first_node)
        last = _bank_index(last_node) if last_node is not None else first
        if first is None or last is None or first[0] != last[0]:
            self.fail(node, f"SIGNAL {name}: expected $IN[n], $OUT[n], $IN[a] TO $IN[b] or $OUT[a] TO $OUT[b]")
        (bank, a), (_bank, b) = first, last
        single = last_node is None
        if bank not in ANALOG and (not 1 <= a <= b <= IO_MAX or b - a + 1 > MAX_BITS):
            self.fail(
                node,
                f"SIGNAL {name}: {b - a + 1} signals from {bank}[{a}]: one, or 2..{MAX_BITS} with TO (a group), "
                f"within 1..{IO_MAX}",
            )
        self.scope.signals[str(name).upper()] = (bank, a, b, single)
        return lambda fr: None

    def s_global_signal_decl(self, node):
        """GLOBAL SIGNAL in a data list: declared as SIGNAL is, and seen by every module."""
        run = self.s_signal_decl(Tree("signal_decl", node.children[1:], node.meta))
        key = str(node.children[1]).upper()
        self.scope.shared_signals[key] = self.scope.signals[key]
        return run

    def _group(self, token) -> tuple | None:
        group = self.scope.signals.get(str(token).upper())
        if group is not None and group[0] in ANALOG:
            self.fail(token, f"{token} is an analog signal ({group[0]}[{group[1]}]): analog I/O is not modelled")
        return group

    def e_var(self, node):
        group = self._group(node.children[0])
        if group is None:
            return super().e_var(node)
        bank, a, b, single = group
        if single:
            stops = bank == "$IN" and not self.take_continue()
            where, name = self.where(node), f"{bank}[{a}]"

            def read_one(fr):
                if stops:
                    fr.m.arrive(where)
                return fr.m.input_signal(name) if bank == "$IN" else fr.m.signals.get(name, False)

            return Src(f"{self.const(read_one)}(fr)")
        stops = bank == "$IN" and not self.take_continue()
        where = self.where(node)

        def read(fr):
            if stops:
                fr.m.arrive(where)
            value = 0
            for bit, n in enumerate(range(a, b + 1)):
                on = fr.m.input_signal(f"$IN[{n}]") if bank == "$IN" else fr.m.signals.get(f"$OUT[{n}]", False)
                value |= int(bool(on)) << bit
            if b - a + 1 == MAX_BITS and value >= 2**31:
                value -= 2**32
            return value

        return Src(f"{self.const(read)}(fr)")

    def s_assign(self, node):
        target_node, value_node = node.children
        is_var = isinstance(target_node, Tree) and target_node.data == "var"
        group = self._group(target_node.children[0]) if is_var else None
        if group is None:
            return super().s_assign(node)
        bank, a, b, single = group
        if bank != "$OUT":
            self.fail(node, f"{target_node.children[0]}: inputs cannot be written (the devices set them)")
        value, where, stops = self.expr(value_node), self.where(node), not self.take_continue()
        bits = b - a + 1
        if single:

            def store_one(fr):
                v = value(fr)
                if not isinstance(v, bool):
                    raise RunError(f"{where}: {target_node.children[0]} ($OUT[{a}]) takes TRUE or FALSE")
                if stops:
                    fr.m.arrive(where)
                fr.m.set_output(f"$OUT[{a}]", v, where)

            return store_one

        def store(fr):
            v = value(fr)
            if isinstance(v, bool) or not isinstance(v, int):
                raise RunError(f"{where}: a signal group takes an INT")
            low = -(2**31) if bits == MAX_BITS else 0
            if not low <= v < (2**31 if bits == MAX_BITS else 2**bits):
                raise RunError(f"{where}: {v} does not fit {bits} signals")
            if stops:
                fr.m.arrive(where)
            for bit, n in enumerate(range(a, b + 1)):
                on = bool((v >> bit) & 1)
                if fr.m.signals.get(f"$OUT[{n}]", False) != on:
                    fr.m.set_output(f"$OUT[{n}]", on, where)
            fr.m.output_written(where)

        return store
