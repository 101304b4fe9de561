"""Generated functions compiled once per shape: sources alike but for their constants' names and strings."""

from __future__ import annotations

import ast
import re
import sys
from types import CodeType, FunctionType

# A numbered name (a registered constant _k or call slot _c, SourceBuilder.const and call_source; a temporary
# _w, SourceBuilder.temp) or a non-empty string literal as repr() writes it. A prefixed string (f'{w}: ...') is
# matched whole and kept, names in its text included. An empty string stays too: every placeholder is a
# non-empty string, so truthiness survives the compiler's folding.
_PARTS = re.compile(
    r"""(?=['"_a-zA-Z])(?<!\w)(?:(?P<f>[a-zA-Z]{1,2}(?:'(?:[^'\\\n]++|\\.)*'|"(?:[^"\\\n]++|\\.)*"))"""
    r"""|(?P<s>'(?:[^'\\\n]++|\\.)+'|"(?:[^"\\\n]++|\\.)+")|(?P<k>_[kcw]\d+)\b)"""
)
_NAME = "_shape_fn"
_PLACEHOLDER_NAME = "_shape_k"
_MARK = "\x00"  # starts every placeholder string: generated code never holds it otherwise


class _Unshaped(Exception):
    """The compiler folded a placeholder into something else ('a' + 'b'): compile this source itself."""


class ShapeCache:
    """Compiles `def NAME(params): body` once per shape and makes each function of that shape from the
    shape's code, its constants' names and strings put back (code.replace): a large program's thousand
    stations differ in little else, and compiling is most of its load. The code is the one compile()
    makes of the function's own source (tests/test_shapes.py compares them)."""

    def __init__(self, filename: str) -> None:
        self.filename = filename
        self.shapes: dict[str, tuple | None] = {}  # shape source -> (code, defaults, kwdefaults); None: unshaped

    def function(self, name: str, params: str, body: str, namespace: dict) -> FunctionType:
        names: dict[str, str] = {}  # constant's name -> its placeholder name
        strings: dict[str, str] = {}  # string literal -> its placeholder literal

        def placeholder(match: re.Match) -> str:
            text = match.group(0)
            if match.lastgroup == "f":  # a prefixed string (f'...'): code, kept as it is, names in it too
                return text
            if match.lastgroup == "k":  # interned: the code's names are then the namespace's keys, not copies
                return names.setdefault(sys.intern(text), f"{_PLACEHOLDER_NAME}{len(names)}")
            return strings.setdefault(text, f"'\\x00{len(strings)}'")

        shape = _PARTS.sub(placeholder, f"def {_NAME}({params}):\n{body}")
        made = self.shapes.get(shape, False)
        if made is False:
            made = self.shapes[shape] = self._compile(shape)
        if made is not None:
            code, defaults, kwdefaults = made
            try:
                code = _put_back(
                    code,
                    {p: n for n, p in names.items()},
                    {f"{_MARK}{i}": _string(literal) for i, literal in enumerate(strings)},
                    name,
                )
            except _Unshaped:
                self.shapes[shape] = None
            else:
                fn = FunctionType(code.replace(co_name=name, co_qualname=name), namespace, name, defaults)
                fn.__kwdefaults__ = kwdefaults
                return fn
        scope: dict = {}
        exec(compile(f"def {name}({params}):\n{body}", self.filename, "exec"), namespace, scope)
        return scope[name]

    def _compile(self, shape: str) -> tuple | None:
        scope: dict = {}
        try:
            exec(compile(shape, self.filename, "exec"), {}, scope)  # defines the function: its defaults
        except Exception:  # a default naming a constant: compiled at each call instead
            return None
        fn = scope[_NAME]
        defaults = (fn.__defaults__ or ()) + tuple((fn.__kwdefaults__ or {}).values())
        if any(isinstance(value, str) and _MARK in value for value in defaults):
            return None
        return fn.__code__, fn.__defaults__, fn.__kwdefaults__


def _string(literal: str) -> str:
    if "\\" not in literal:
        return literal[1:-1]
    return ast.literal_eval(literal)


def _put_back(code: CodeType, names: dict[str, str], strings: dict[str, str], name: str) -> CodeType:
    """The code with the placeholders' names and strings replaced, nested code included (named after
    the function it is in)."""
    if any(n.startswith(_PLACEHOLDER_NAME) for n in code.co_cellvars + code.co_freevars):
        raise _Unshaped
    return code.replace(
        co_names=tuple(names[n] if n.startswith(_PLACEHOLDER_NAME) else n for n in code.co_names),
        co_varnames=tuple(names[n] if n.startswith(_PLACEHOLDER_NAME) else n for n in code.co_varnames),
        co_consts=tuple(_value(c, names, strings, name) for c in code.co_consts),
        co_qualname=code.co_qualname.replace(_NAME, name, 1),
    )


def _value(value, names: dict[str, str], strings: dict[str, str], name: str):
    kind = type(value)
    if kind is str:
        if _MARK not in value:
            return value
        if value not in strings:
            raise _Unshaped
        return strings[value]
    if kind is tuple:
        return tuple(_value(v, names, strings, name) for v in value)
    if kind is frozenset:
        return frozenset(_value(v, names, strings, name) for v in value)
    if kind is CodeType:
        return _put_back(value, names, strings, name)
    if kind is bytes and _MARK.encode() in value:
        raise _Unshaped
    return value
