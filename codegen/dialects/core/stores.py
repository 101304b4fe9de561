"""Compiler mixin for stores: coercions, assignment paths (copy along the path) and setters."""

from __future__ import annotations

import numpy as np
from lark import Token, Tree

from codegen.dialects.core.values import F32, RunError, f32, show


class Stores:
    """Values stored into variables, fields and elements, with the dialect's coercions."""

    COERCE_UNCHANGED: dict[str, str] = {}
    INT_RANGE: tuple[int, int] | None = None  # a language's integer range: a store beyond it is an error
    RECORD_TYPES: frozenset = frozenset()  # records of exactly this type pass coerce() unchanged
    LIKE_UNCHANGED: frozenset = frozenset({F32})  # coerce_like(old, new) is new when both have this type

    def coerce(self, type_name: str | None, value, where: str):
        return value

    def coerce_array(self, type_name: tuple, value, where: str, shown: str):
        """A value stored as an array of type_name = (element type, size or None); shown names the
        element type in messages. An array of float32 numbers of a float32 element type (in
        COERCE_UNCHANGED) is stored as it is: arrays are never changed in place."""
        element, size = type_name
        if not isinstance(value, list):
            raise RunError(f"{where}: expected an array of {shown}")
        if size is not None and len(value) != size:
            raise RunError(f"{where}: expected {size} elements, got {len(value)}")
        if self.COERCE_UNCHANGED.get(element) == "_F32" and all(type(v) is F32 for v in value):
            return value
        return [self.coerce(element, v, where) for v in value]

    def coerce_like_source(self, old: str, value: str, where: str) -> str:
        """Source of coerce_like(old, value) (both plain names): value itself when both have one
        type that the dialect stores unchanged."""
        call = f"{self.const(self.coerce_like)}({old}, {value}, {where!r})"
        unchanged = self.const(self.LIKE_UNCHANGED)
        same_record = f"type({old}) is _Record and {value}.type == {old}.type is not None"  # a typed record
        return (
            f"({value} if (_tv := type({value})) is type({old}) and (_tv in {unchanged} or {same_record}) else {call})"
        )

    def coerce_source(self, type_name, value: str, where: str) -> str:
        """Source of coerce(type_name, value): the value itself when it already has the type.
        value is a plain name; where is the source of the location text."""
        if type_name is None:
            return value
        call = f"{self.const(self.coerce)}({self.const(type_name)}, {value}, {where})"
        if isinstance(type_name, str) and type_name in self.COERCE_UNCHANGED:
            fast = self.COERCE_UNCHANGED[type_name]
            if fast == "int" and self.INT_RANGE is not None:
                low, high = self.INT_RANGE
                return f"({value} if type({value}) is int and {low} <= {value} <= {high} else {call})"
            return f"({value} if type({value}) is {fast} else {call})"
        if isinstance(type_name, str) and type_name in self.RECORD_TYPES:
            return f"({value} if type({value}) is _Record and {value}.type == {type_name!r} else {call})"
        return call

    def assign_target(self, node):
        """The lvalue node of an assignment target (a dialect may unwrap its own wrapper rule)."""
        return node

    def store_lines(self, node, value: str) -> list[str]:
        """Lines that store `value` (a plain name) into a variable, field or element. A field or
        element is stored as a changed copy of its record or array, stored in turn into the one
        holding it, up to the variable. The path is read once, outermost first, so an index
        expression is evaluated once."""
        steps = []  # (kind, key node, node): outermost last
        node = self.assign_target(node)
        while isinstance(node, Tree) and (node.data == "field" or (node.data == "index" and len(node.children) == 2)):
            steps.append((node.data, node.children[1], node))
            node = self.assign_target(node.children[0])
        if not (isinstance(node, Token) or node.data == "var"):
            self.fail(node, f"cannot assign to {node.data}")
        if not steps:
            return self.var_store_lines(node, value)
        steps.reverse()
        lines, keys = [f"_r0 = {self.src(node)}"], []
        for depth, (kind, key_node, step) in enumerate(steps):
            slot, where = f"_r{depth}", repr(self.where(step))
            if kind == "field":
                key = repr(self.norm(str(key_node)))
                lines += [
                    f"if not isinstance({slot}, _Record) or {key} not in {slot}:",
                    f"    _nofield_set({slot}, {str(key_node)!r}, {where})",
                ]
            else:
                key = f"_i{depth}"
                lines += [
                    f"{key} = {self.index_source(key_node)}",
                    f"if not isinstance({slot}, list) or not 0 <= {key} < len({slot}):",
                    f"    _badindex({key} + {self.index_base}, {where})",
                ]
            keys.append(key)
            if depth + 1 < len(steps):
                lines.append(f"_r{depth + 1} = {slot}[{key}]")
        inner = value
        for depth in reversed(range(len(steps))):
            slot, key, (kind, _key_node, step) = f"_r{depth}", keys[depth], steps[depth]
            lines += [
                f"_c = {slot}.shallow()" if kind == "field" else f"_c = list({slot})",
                f"_o = {slot}[{key}]",
                f"_c[{key}] = {self.coerce_like_source('_o', inner, self.where(step))}",
                f"{slot} = _c",
            ]
            inner = slot
        return lines + self.var_store_lines(node, "_r0")

    def var_store_lines(self, node, value: str) -> list[str]:
        """Lines storing value into a variable, as lvalue()'s set_var: the routine's variable,
        else a global, else a new variable (where the language makes one)."""
        token = node if isinstance(node, Token) else node.children[0]
        key = self.norm(str(token))
        where = repr(self.where(token))
        if self.local_types is not None and key in self.local_types:
            return [f"V[{key!r}] = {self.coerce_source(self.local_types[key], value, where)}"]
        if type(self).coerce is Stores.coerce:  # untyped language: values stored as they are
            local, glob = value, value
        else:
            coerce, unchanged = self.const(self.coerce), self.const(self.unchanged_types())
            # the value itself where it has the type the variable was declared with (as coerce_source)
            local = f"({value} if type({value}) is {unchanged}.get(fr.types.get({key!r})) else "
            local += f"{coerce}(fr.types.get({key!r}), {value}, {where}))"
            glob = f"({value} if type({value}) is {unchanged}.get(m.global_types.get({key!r})) else "
            glob += f"{coerce}(m.global_types.get({key!r}), {value}, {where}))"
        return [
            f"if {key!r} in V: V[{key!r}] = {local}",
            f"elif {key!r} in G: G[{key!r}] = {glob}",
            f"else: {self.const(self.new_variable)}(fr, {key!r}, {value}, {where})",
        ]

    def unchanged_types(self) -> dict:
        """The declared types whose values coerce() stores as they are when they already have its Python type (as
        coerce_source: COERCE_UNCHANGED; an integer type with a range is checked by coerce), by type name."""
        made = self.__dict__.get("_unchanged_types")
        if made is None:
            kinds = {"_F32": F32, "bool": bool, "int": int if self.INT_RANGE is None else None}
            made = {name: kinds[fast] for name, fast in self.COERCE_UNCHANGED.items() if kinds[fast] is not None}
            self.__dict__["_unchanged_types"] = made  # one table, one constant of the generated code
        return made

    def lvalue(self, node):
        """A setter(frame, value) for a variable, an array element or a record field (by-reference
        arguments, loop counters): the lines of store_lines() compiled into a function."""
        lines = self.guarded(self.store_lines(node, "_v"), self.where(node))
        return self.function(lines, "fr, _v", f"{self.name}_{self.routine_name}_store")

    def new_variable(self, fr, key, value, where):
        fr.vars[key] = value

    def coerce_like(self, old, value, where):
        """Store value where old was: keep the slot's number type."""
        if isinstance(old, np.floating) and not isinstance(value, bool):
            try:
                return f32(value)
            except (TypeError, ValueError):
                raise RunError(f"{where}: cannot store {show(value)} in a number") from None
        return value


# --- number formatting shared by message instructions -----------------------------------------
