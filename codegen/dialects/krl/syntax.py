"""The KRL parser: grammar.lark (beside interpreter.py, whose path keys the cached parser) to a lark tree."""

from __future__ import annotations

import re
from pathlib import Path

from lark import Tree

from codegen.dialects.core.kept import STORE
from codegen.dialects.core.larkdoor import Start
from codegen.dialects.core.parsing import parse_with_grammar
from codegen.dialects.core.values import RunError

INTERPRETER = str(Path(__file__).with_name("interpreter.py"))  # the cache key Dialect.parse and check use
# Words of other languages people write in KRL, and what KRL has instead (KSS 8 programming manual, program
# flow control: IF ... THEN ... ELSE ... ENDIF, SWITCH ... CASE ... DEFAULT ... ENDSWITCH; no ELSEIF)
FOREIGN = {"ELSEIF": "KRL has no ELSEIF: nest an IF in the ELSE branch (IF ... ELSE IF ... ENDIF ENDIF) or use SWITCH"}
_FOREIGN_LINE = re.compile(r"^(\s*)(" + "|".join(FOREIGN) + r")\b", re.IGNORECASE)
_ERROR_LINE = re.compile(r":(\d+):\d+: syntax error")


# A line that starts a routine or a data list: a file's units, parsed one by one (see parse)
_UNIT = re.compile(r"^[\t ]*(?:GLOBAL[\t ]+)?(?:DEF|DEFFCT|DEFDAT)(?![\w$])", re.IGNORECASE)


def parse(text: str, filename: str = "<krl>", positions: bool = True) -> Tree:
    """A .src or .dat's tree. While the parse store keeps trees (core/kept.py), its routines and data lists are each
    parsed on their own and kept, so that an edit inside one routine parses that routine again, not the file; where
    a unit does not parse, the whole text is parsed for the error (which may lie across units: a missing END)."""
    try:
        units = _units(text) if STORE.shares else [text]
        if len(units) > 1:
            try:
                return _joined([parse_with_grammar(INTERPRETER, unit, filename) for unit in units])
            except RunError:
                pass
        return parse_with_grammar(INTERPRETER, text, filename, positions)
    except RunError as exc:
        at = _ERROR_LINE.search(str(exc))
        if at is None:
            raise
        for n, line in enumerate(text.split("\n")[: int(at.group(1))], 1):  # a foreign word at or before it
            word = _FOREIGN_LINE.match(line)
            if word:
                column = len(word.group(1)) + 1
                raise RunError(f"{filename}:{n}:{column}: syntax error: {FOREIGN[word.group(2).upper()]}") from None
        raise


def _units(text: str) -> list[str]:
    """The text cut before each line that starts a routine or a data list; each part preceded by as many line ends
    as the text has before it, so that its tree's lines are the file's (the grammar's _NL takes them as one token)."""
    lines = text.split("\n")
    starts = [i for i, line in enumerate(lines) if _UNIT.match(line)]
    if not starts or starts[0] != 0:
        starts.insert(0, 0)
    ends = [*starts[1:], len(lines)]
    return ["\n" * a + "\n".join(lines[a:b]) for a, b in zip(starts, ends, strict=True)]


def _joined(trees: list[Tree]) -> Tree:
    """The file's tree from its units' (each a `start` of its routines and data lists), starting where its first
    unit's first child does, as the whole text's parse would."""
    children = [child for tree in trees for child in tree.children]
    joined = Tree("start", children)
    first = next((t for t in trees if t._meta is not None and not t._meta.empty), None)
    if first is not None:
        meta = joined._meta = Start(first._meta.line, first._meta.column)
        meta.container_line, meta.container_column = first._meta.container_line, first._meta.container_column
    return joined
