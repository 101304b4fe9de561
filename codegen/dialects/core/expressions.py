"""Compiler mixin for expressions: literals, variables, operators, indexing and fields."""

from __future__ import annotations

import math
import operator

import numpy as np
from lark import Token, Tree

from codegen.dialects.core.source import Src
from codegen.dialects.core.values import F32_MAX, MISSING, RunError, f32, whole_index

NUMBERS = (int, float, np.float32)  # what a number literal compiles to (not bool: a literal of its own)


class Expressions:
    """Expressions compiled to Python source (`Src`) or, without a source form, closures."""

    _negated_literal = False  # e_number of the operand of a minus (an int literal's range is one wider below 0)

    def expr(self, node):
        """A callable fr -> value; when the rule has a source form, `.source` holds it."""
        compiled = self._compile_expr(node)
        if not isinstance(compiled, Src):
            return compiled
        value = self.number_constant(compiled)
        if value is not None:  # a literal: no source to compile (a large program's globals hold thousands)
            fn = _returning(value)
        else:
            fn = self.function(self.guarded([f"return {compiled}"], self.where(node)))
        fn.source = compiled
        return fn

    def number_constant(self, source: Src) -> int | float | np.float32 | None:
        """The number a source stands for when it is a registered number (e_number's const), else None."""
        value = self.ns.get(source) if source.startswith("_k") else None
        return value if type(value) in NUMBERS else None

    def _compile_expr(self, node):
        if isinstance(node, Token):
            compiled = self.token_expr(node)
        else:
            method = getattr(self, f"e_{node.data}", None)
            if method is None:
                self.fail(node, f"unsupported expression {node.data}")
            compiled = method(node)
        source = getattr(compiled, "source", None)
        return source if source is not None else compiled

    def token_expr(self, token: Token):
        if token.type == "NAME":
            return self.var_source(token)
        self.fail(token, f"unexpected token {token}")

    def e_number(self, node):
        text = str(node.children[0])
        shown = text if len(text) <= 20 else text[:20] + "..."
        try:
            with np.errstate(over="ignore"):  # past float32's range: refused below, in the program's words
                value = self.number(text)
        except (ValueError, OverflowError):
            self.fail(node, f"number {shown} has more digits than a controller reads")
        if isinstance(value, int):
            low, high = self.INT_RANGE or (None, None)
            if high is not None and value > (-low if self._negated_literal else high):
                self.fail(node, f"number {shown} is beyond the controller's integers ({low}..{high}, 32-bit)")
        elif not math.isfinite(value):
            limit = f"32-bit floating point: at most {F32_MAX:.7g}"
            self.fail(node, f"number {shown} is beyond the controller's numbers ({limit})")
        return Src(self.const(value))

    def e_string(self, node):
        return Src(repr(self.string_value(str(node.children[0]))))

    def string_value(self, text: str) -> str:
        return text[1:-1]

    def e_true(self, node):
        return Src("True")

    def e_false(self, node):
        return Src("False")

    def e_var(self, node):
        return self.var_source(node.children[0])

    def var_source(self, token) -> Src:
        """A routine's variables, then the globals; anything else (errors, the controller's own
        names) is left to the dialect's var_reader."""
        key = repr(self.norm(str(token)))
        if self.local_types is not None and self.norm(str(token)) in self.local_types:
            return Src(f"V[{key}]")  # a declared local or parameter: always in the frame
        fallback = self.const(self.var_reader(token))
        return Src(f"(V[{key}] if {key} in V else G[{key}] if {key} in G else {fallback}(fr))")

    def var_reader(self, token):
        name = str(token)  # not the token: a token kept alive keeps the parse tree's memory from the system
        key = self.norm(name)
        where = self.where(token)

        def read(fr):
            value = fr.vars.get(key, MISSING)
            if value is MISSING:
                value = fr.m.globals.get(key, MISSING)
                if value is MISSING:
                    raise RunError(f"{where}: undefined variable {name}")
            return value

        return read

    def e_neg(self, node):
        child = node.children[0]
        self._negated_literal = isinstance(child, Tree) and child.data == "number"  # -2147483648 is an int
        try:
            operand = self.src(child)
        finally:
            self._negated_literal = False
        value = self.number_constant(operand)
        if value is not None:  # a negative literal: the number itself (what -x gives when run)
            return Src(self.const(-value))
        return Src(f"(-{operand})")

    def _binary_source(self, node, symbol: str) -> Src:
        left, right = (self.src(c) for c in node.children)
        return Src(f"({left} {symbol} {right})")

    def _binary_call(self, node, function) -> Src:
        left, right = (self.src(c) for c in node.children)
        return Src(f"{self.const(function)}({left}, {right})")

    def e_add(self, node):
        if type(self).add is Expressions.add:
            return self._binary_source(node, "+")
        return self._binary_call(node, self.add)

    def add(self, a, b):
        return a + b

    def e_sub(self, node):
        return self._binary_source(node, "-")

    def e_mul(self, node):
        return self._binary_source(node, "*")

    def e_div(self, node):
        return self._binary_call(node, self.divide)

    def divide(self, a, b):
        if self.int_division and isinstance(a, int) and isinstance(b, int):
            if b == 0:
                raise ZeroDivisionError
            return int(a / b)
        if b == 0:
            raise ZeroDivisionError
        return f32(a) / f32(b) if not isinstance(a, float) else a / b

    def e_mod(self, node):
        return self._binary_source(node, "%")

    # Boolean operators: the operands are the first and last children (some grammars keep
    # the operator keyword token between them). Results are Python bools.
    def e_not_(self, node):
        return Src(f"(not {self.src(node.children[-1])})")

    def e_and_(self, node):
        left, right = self.src(node.children[0]), self.src(node.children[-1])
        return Src(f"(True if {left} and {right} else False)")

    def e_or_(self, node):
        left, right = self.src(node.children[0]), self.src(node.children[-1])
        return Src(f"(True if {left} or {right} else False)")

    def e_xor(self, node):
        left, right = self.src(node.children[0]), self.src(node.children[-1])
        return Src(f"(bool({left}) != bool({right}))")

    e_exor = e_xor

    OPERATOR_SYMBOLS = {
        operator.eq: "==",
        operator.ne: "!=",
        operator.lt: "<",
        operator.le: "<=",
        operator.gt: ">",
        operator.ge: ">=",
    }

    def e_compare(self, node):
        left_node, op_token, right_node = node.children
        op = self.compare_ops[str(op_token).upper() if self.case_insensitive else str(op_token)]
        left, right = self.src(left_node), self.src(right_node)
        symbol = self.OPERATOR_SYMBOLS.get(op)
        if symbol is None:
            return Src(f"(True if {self.const(op)}({left}, {right}) else False)")
        return Src(f"(True if {left} {symbol} {right} else False)")

    def e_index(self, node):
        """An array element inline; anything else (a record's field by number, an index out of
        range) through index_value()."""
        base_node, index_node = node.children
        seq, i, offset = self.temp(), self.temp(), self.index_base
        base, index = self.src(base_node), self.index_source(index_node)
        return Src(
            f"({seq}[{i}] if ((type({seq} := {base}) is list) & (({i} := {index}) >= 0)) and {i} < len({seq})"
            f" else _index({seq}, {i} + {offset}, {offset}, {self.where(node)!r}))"
        )

    def index_source(self, index_node) -> str:
        """Source of a 0-based index; a literal index is folded into a number. Where the language takes only whole
        indexes (whole_indexes), any other is a run-time error naming it; else the index is cut to a whole number."""
        if isinstance(index_node, Tree) and index_node.data == "number":
            value = self.number(str(index_node.children[0]))
            if float(value) == int(value):
                return str(int(value) - self.index_base)
        if self.whole_indexes:
            return f"{self.const(whole_index)}({self.src(index_node)}, {self.where(index_node)!r}) - {self.index_base}"
        return f"int({self.src(index_node)}) - {self.index_base}"

    def e_field(self, node):
        base_node, name = node.children
        base = self.src(base_node)
        key = repr(self.norm(str(name)))
        return Src(
            f"(_t[{key}] if isinstance(_t := {base}, dict) and {key} in _t "
            f"else _nofield(_t, {str(name)!r}, {self.where(node)!r}))"
        )


def _returning(value):
    """fr -> value, a closure over a shared code object (nothing compiled)."""

    def constant(fr):
        return value

    return constant
