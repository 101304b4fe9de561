"""Python-source building blocks of the compiler: expression source, inline statements, lazy stores."""

from __future__ import annotations

import re
import sys

import numpy as np
from lark import Token

from codegen.dialects.core.shapes import ShapeCache
from codegen.dialects.core.values import RunError

# numbers by value, the floats by their bits (-0.0 is not 0.0; float.hex keeps the sign but gives every NaN one
# text: no literal is a Python-float NaN, and a NaN's payload and sign change no result)
_NUMBER_KEYS = {int: int, bool: bool, float: float.hex, np.float32: np.float32.tobytes, np.float64: np.float64.tobytes}
FRAME_NAMES = re.compile(r"\b(m|V|G)\b")


def indent(lines: list[str]) -> list[str]:
    return ["    " + line for line in lines]


class Src(str):
    """Python source of an expression. It may use `fr` (the frame), `m` (the machine), `V` (the
    frame's variables), `G` (the globals) and the names the compiler registered with const()."""


class Inline:
    """A statement as Python source lines: block() inlines them; called directly, the lines are
    compiled once into a function. The lines end a block with `return signal` for RETURN, EXIT..."""

    __slots__ = ("compiler", "fn", "lines")

    def __init__(self, compiler: SourceBuilder, lines: list[str]) -> None:
        self.compiler = compiler
        self.lines = lines
        self.fn = None

    def __call__(self, fr):
        if self.fn is None:
            self.fn = self.compiler.function([*self.lines, "return None"])
        return self.fn(fr)


class LazyStore:
    """A by-reference argument's setter, compiled (in the context of the routine that passes the
    argument) only when a callee writes it back: most arguments are passed by value."""

    __slots__ = ("compiler", "context", "fn", "node")

    def __init__(self, compiler: SourceBuilder, node) -> None:
        self.compiler, self.node, self.fn = compiler, node, None
        self.context = (compiler.local_types, compiler.routine_name)

    def __call__(self, fr, value) -> None:
        if self.fn is None:
            compiler = self.compiler
            saved = compiler.local_types, compiler.routine_name
            compiler.local_types, compiler.routine_name = self.context
            try:
                self.fn = compiler.lvalue(self.node)
            finally:
                compiler.local_types, compiler.routine_name = saved
        self.fn(fr, value)


class SourceBuilder:
    """Compiler mixin: the namespace of the generated source, functions compiled from lines, and
    source positions for messages."""

    _shapes: ShapeCache | None = None

    # --- Python source ----------------------------------------------------------------------
    def temp(self) -> str:
        """A fresh local name for a value used twice within one expression."""
        self._temps += 1
        return f"_w{self._temps}"

    def const(self, value) -> str:
        """A name under which the generated source sees value (a closure, a number, a table); one name per
        number (by type and every bit: -0.0 is not 0.0), however many literals spell it."""
        kind = type(value)
        number = kind in _NUMBER_KEYS
        key = (kind, _NUMBER_KEYS[kind](value)) if number else id(value)
        name = self._consts.get(key)
        if name is None or (not number and self.ns[name] is not value):  # an id: of this object, still alive?
            name = sys.intern(f"_k{len(self.ns)}")  # the code objects' names are then this string itself
            self.ns[name] = value
            self._consts[key] = name
        return name

    def function(self, lines: list[str], params: str = "fr", name: str | None = None, prologue: bool = True):
        """Compile statement lines into a function (of the frame `fr` unless params say more); the
        prologue binds m, V and G where the lines use them."""
        head = []
        if prologue:
            used = set(FRAME_NAMES.findall("\n".join(lines)))
            if "m" in used or "G" in used:
                head.append("m = fr.m")
            if "V" in used:
                head.append("V = fr.vars")
            if "G" in used:
                head.append("G = m.globals")
        name = re.sub(r"\W", "_", name or f"{self.name}_{self.routine_name}")  # shows in tracebacks and profiles
        if self._shapes is None:
            self._shapes = ShapeCache(f"<{self.filename}: compiled>")
        return self._shapes.function(name, params, "\n".join([*indent(head), *indent(lines)]) + "\n", self.ns)

    def guarded(self, lines: list[str], where: str) -> list[str]:
        """Lines whose operator errors (a number plus a string, a division by zero, a NaN index)
        become RunErrors naming the statement."""
        return [
            "try:",
            *indent(lines),
            "except (TypeError, ZeroDivisionError, ValueError, OverflowError, FloatingPointError) as _e:",
            f"    raise _operror({where!r}, _e) from None",
        ]

    MAX_SOURCE_DEPTH = 24  # expression levels inline before a subexpression gets its own function

    def src(self, node) -> Src:
        """The Python source of an expression; a rule without one is called as its closure. A deep
        subexpression is compiled into a function of its own (Python limits nesting in source)."""
        if self._source_depth >= self.MAX_SOURCE_DEPTH:
            outer, self._source_depth = self._source_depth, 0
            try:
                return Src(f"{self.const(self.expr(node))}(fr)")
            finally:
                self._source_depth = outer
        self._source_depth += 1
        try:
            compiled = self._compile_expr(node)
        finally:
            self._source_depth -= 1
        return compiled if isinstance(compiled, Src) else Src(f"{self.const(compiled)}(fr)")

    def source_of(self, compiled) -> Src:
        """Source of what expr() or stmt() returned: inline text or a call of the closure."""
        source = getattr(compiled, "source", None)
        return source if source is not None else Src(f"{self.const(compiled)}(fr)")

    def body_lines(self, compiled) -> list[str]:
        """Lines that run a compiled statement or block inline and pass its signal on."""
        if isinstance(compiled, Inline):
            return compiled.lines
        inline = getattr(compiled, "inline", None)
        if (
            inline is not None
            and max((len(x) - len(x.lstrip(" ")) for x in inline), default=0) < self.MAX_INLINE_INDENT
        ):
            return inline
        return [f"_s = {self.const(compiled)}(fr)", "if _s is not None:", "    return _s"]

    # A block nested deeper than this is called rather than inlined (Python allows 20 nested
    # try blocks and 100 indentation levels in one function).
    MAX_INLINE_INDENT = 4 * 12

    # --- helpers ----------------------------------------------------------------------------
    def norm(self, name: str) -> str:
        return name.upper() if self.case_insensitive else name

    def where(self, node) -> str:
        meta = getattr(node, "meta", None)
        line = getattr(node, "line", None) or (getattr(meta, "line", None) if meta and not meta.empty else None)
        col = getattr(node, "column", None) or (getattr(meta, "column", None) if meta and not meta.empty else None)
        if line is None:
            return self.filename
        return f"{self.filename}:{line}:{col}"

    def line(self, node) -> int:
        meta = getattr(node, "meta", None)
        if isinstance(node, Token):
            return node.line or 0
        return meta.line if meta is not None and not meta.empty else 0

    def fail(self, node, message: str):
        raise RunError(f"{self.where(node)}: {message}")
