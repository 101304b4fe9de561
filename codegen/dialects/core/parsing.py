"""Parser glue: each dialect's grammar.lark as a cached LALR parser, syntax errors as RunErrors."""

from __future__ import annotations

import re
from functools import cache
from pathlib import Path

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedInput

from codegen.dialects.core.kept import STORE
from codegen.dialects.core.larkdoor import mark_starts, open_cached
from codegen.dialects.core.recognize import Recognizer
from codegen.dialects.core.values import RunError

LINE_MAX = 10_000  # characters per program line: the generated ones stay under 1,000
SHARED_GRAMMARS = str(Path(__file__).parent)  # terminals.lark: what the grammars import (`%import terminals`)


def open_grammar(interpreter_file: str, **options) -> Lark:
    """lark's LALR parser of the grammar.lark beside a dialect's interpreter, with lark's options."""
    return open_cached("grammar.lark", interpreter_file, parser="lalr", import_paths=[SHARED_GRAMMARS], **options)


@cache
def grammar_parser(interpreter_file: str, positions: bool = True, postlex=None) -> Lark:
    """The LALR parser of the grammar.lark beside a dialect's interpreter; without positions it
    parses twice as fast (syntax errors still carry them). With positions, each tree's meta has the
    line and column where it starts (larkdoor.mark_starts), all the interpreter reads. postlex: a dialect's
    filter of the token stream (lark's postlex: e.g. line ends inside brackets dropped), one object per
    dialect (the parsers are cached by it)."""
    parser = open_grammar(interpreter_file, propagate_positions=False, postlex=postlex)
    if positions:
        mark_starts(parser)
    return parser


def _bounded(text: str, filename: str) -> str:
    """The text with a final line break; a RunError for a line longer than LINE_MAX (parsed, it would
    take seconds and gigabytes to refuse: nested too deeply)."""
    if not text.endswith("\n"):
        text += "\n"
    long_line = next((i for i, line in enumerate(text.split("\n"), start=1) if len(line) > LINE_MAX), None)
    if long_line is not None:
        raise RunError(f"{filename}:{long_line}:1: line longer than {LINE_MAX} characters")
    return text


def parse_with_grammar(interpreter_file: str, text: str, filename: str, positions: bool = True, postlex=None) -> Tree:
    """Parse a program; a syntax error becomes a RunError naming file:line:column. While the parse store keeps
    trees (kept.py), the tree (with positions, asked for or not) comes from there where this text of this file was
    parsed before: it is shared, not to be changed."""
    if not STORE.shares:
        return _parse(interpreter_file, text, filename, postlex, positions)
    parse = lambda: _parse(interpreter_file, text, filename, postlex, True)  # noqa: E731
    return STORE.tree((interpreter_file, postlex), filename, text, parse)


def _parse(interpreter_file: str, text: str, filename: str, postlex, positions: bool) -> Tree:
    text = _bounded(text, filename)
    parser = grammar_parser(interpreter_file, positions, postlex)
    try:
        return parser.parse(text)
    except UnexpectedInput as exc:
        raise syntax_error(exc, filename, parser) from None


@cache
def grammar_recognizer(interpreter_file: str) -> Recognizer:
    """The fast yes/no check of the grammar beside a dialect's interpreter (codegen/dialects/core/recognize.py)."""
    return Recognizer(grammar_parser(interpreter_file, False))


def check_with_grammar(interpreter_file: str, text: str, filename: str, postlex=None) -> None:
    """Raise as parse_with_grammar would, without building a tree: the recognizer says yes to a
    program lark would parse; whatever it does not accept, lark parses for the verdict and the
    message (generate's check of every program it writes). The recognizer sees the tokens
    without the postlex: a text it accepts has nothing the postlex would drop (a grammar that has no place
    for the dropped tokens), so it accepts only what the full parse accepts."""
    text = _bounded(text, filename)
    if not grammar_recognizer(interpreter_file).accepts(text):
        parse_with_grammar(interpreter_file, text, filename, positions=False, postlex=postlex)


# What a user calls the terminals whose pattern is not a word or a symbol of the language.
_TERMS = {
    "NAME": "a name",
    "NUMBER": "a number",
    "INT": "an integer",
    "STRING": "a string",
    "_NL": "the end of the line",
    "COMMENT": "a comment",
    "HEADER": "a & line",
}
_ALTERNATIVE = re.compile(r"\(\?i:([^()]*)\)|([^|()?:]+)")


def _spelled(pattern) -> list[str]:
    """The words or symbols a terminal's pattern stands for, as written in a program: a literal, or
    each alternative of a regex made of literals only ("C_PTP"i | "C_DIS"i); [] when it is a real
    regex (a name, a number)."""
    if pattern.type == "str":
        return [pattern.value]
    value = pattern.value
    if value.startswith("(?:") and value.endswith(")"):
        value = value[3:-1]
    words = []
    for part in value.split("|"):
        match = _ALTERNATIVE.fullmatch(part)
        literal = (match.group(1) or match.group(2)) if match else None
        literal = literal.replace("\\b", "") if literal else None
        if not literal or re.search(r"[\\\[\]().*+?{}^$]", literal.replace("\\[", "").replace("\\]", "")):
            return []
        words.append(literal.replace("\\", ""))
    caseless = "i" in pattern.flags or "(?i:" in pattern.value
    return [w.upper() if caseless else w for w in words]


def syntax_error(exc, filename: str, parser) -> RunError:
    """file:line:column, the token found and what the grammar expected there, in the program's words
    (keywords and symbols quoted, "a name", "a number" ...), never the grammar's rule names."""
    names = sorted(getattr(exc, "expected", None) or getattr(exc, "allowed", None) or [])
    patterns = {t.name: t.pattern for t in parser.terminals}
    shown: list[str] = []
    for name in names:
        pattern = patterns.get(name)
        words = _spelled(pattern) if pattern is not None else []
        described = [repr(w) for w in words] or [_TERMS.get(name, name.lower().strip("_").replace("_", " "))]
        shown.extend(d for d in described if d not in shown)
    token = getattr(exc, "token", None)
    found = f" at {str(token)!r}" if token is not None and str(token).strip() else ""
    if token is None and getattr(exc, "char", None):
        found = f" at {exc.char!r}"
    expected = ", ".join(shown) if shown else "something else"
    return RunError(f"{filename}:{exc.line}:{exc.column}: syntax error{found}, expected one of {expected}")


def node_start(node) -> tuple[int, int]:
    """Where a parsed node starts (line, column): its meta, else its first token; (0, 0) for a node without one."""
    meta = getattr(node, "meta", None)
    if meta is not None and not getattr(meta, "empty", True):
        return meta.line, meta.column
    for token in node.scan_values(lambda t: isinstance(t, Token)):
        return token.line, token.column
    return 0, 0
