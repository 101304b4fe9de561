"""Parser glue: each dialect's grammar.lark as a cached LALR parser, syntax errors as RunErrors."""

from __future__ import annotations

from functools import cache

from lark import Lark, Tree
from lark.exceptions import UnexpectedInput

from codegen.dialects.core.values import RunError


@cache
def grammar_parser(interpreter_file: str, positions: bool = True) -> Lark:
    """The LALR parser of the grammar.lark beside a dialect's interpreter; without positions it
    parses twice as fast (syntax errors still carry them)."""
    return Lark.open("grammar.lark", rel_to=interpreter_file, parser="lalr", propagate_positions=positions)


def parse_with_grammar(interpreter_file: str, text: str, filename: str, positions: bool = True) -> Tree:
    """Parse a program; a syntax error becomes a RunError naming file:line:column."""
    if not text.endswith("\n"):
        text += "\n"
    parser = grammar_parser(interpreter_file, positions)
    try:
        return parser.parse(text)
    except UnexpectedInput as exc:
        raise syntax_error(exc, filename, parser) from None


def syntax_error(exc, filename: str, parser) -> RunError:
    """file:line:column, the token found and what the grammar expected there."""
    names = sorted(getattr(exc, "expected", None) or getattr(exc, "allowed", None) or [])
    patterns = {t.name: t.pattern for t in parser.terminals}
    shown = []
    for name in names:
        pattern = patterns.get(name)
        literal = getattr(pattern, "value", None) if pattern is not None and pattern.type == "str" else None
        shown.append(repr(literal) if literal else name.lower())
    token = getattr(exc, "token", None)
    found = f" at {str(token)!r}" if token is not None and str(token).strip() else ""
    if token is None and getattr(exc, "char", None):
        found = f" at {exc.char!r}"
    expected = ", ".join(shown) if shown else "something else"
    return RunError(f"{filename}:{exc.line}:{exc.column}: syntax error{found}, expected one of {expected}")
