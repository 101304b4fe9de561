"""The KRL parser: grammar.lark (beside interpreter.py, whose path keys the cached parser) to a lark tree."""

from __future__ import annotations

import re
from pathlib import Path

from lark import Tree

from codegen.dialects.core.parsing import parse_with_grammar
from codegen.dialects.core.values import RunError

INTERPRETER = str(Path(__file__).with_name("interpreter.py"))  # the cache key Dialect.parse and check use
# Words of other languages people write in KRL, and what KRL has instead (KSS 8 programming manual, program
# flow control: IF ... THEN ... ELSE ... ENDIF, SWITCH ... CASE ... DEFAULT ... ENDSWITCH; no ELSEIF)
FOREIGN = {"ELSEIF": "KRL has no ELSEIF: nest an IF in the ELSE branch (IF ... ELSE IF ... ENDIF ENDIF) or use SWITCH"}
_FOREIGN_LINE = re.compile(r"^(\s*)(" + "|".join(FOREIGN) + r")\b", re.IGNORECASE)
_ERROR_LINE = re.compile(r":(\d+):\d+: syntax error")


def parse(text: str, filename: str = "<krl>", positions: bool = True) -> Tree:
    try:
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
