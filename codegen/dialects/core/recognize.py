"""A fast yes/no grammar check of generated programs: lark's LALR tables and lexers, memoised per line shape."""

from __future__ import annotations

import re

from lark import Lark
from lark.exceptions import UnexpectedCharacters

from codegen.dialects.core.larkdoor import lexer_state, tables

# A chunk ends where a run of white space holding a line break ends: no token of any of our grammars
# crosses such a run except white space itself (strings and comments stop at a line break), so a chunk
# lexes alone as it does in the whole text (tests/test_recognize.py checks this of every grammar).
CHUNK_END = re.compile(r"[\t \f\r]*\n[\t \f\r\n]*")
# Every terminal of every grammar spells digits as the class \d or 0-9, never one digit (tested):
# a chunk with each digit made 0 lexes to the same terminals at the same places, so parses alike.
DIGITS_AS_ZERO = str.maketrans("123456789", "000000000")
MEMO_MAX = 200_000  # chunks remembered per grammar (a 1,000-station cell's programs: under 10,000)


class Recognizer:
    """Says whether a text is in a grammar's language, with lark's parse table and its contextual
    lexers (the same tokens, the same shifts and reductions), but no tree, no positions, and one
    parse per (parser stack, chunk shape): the thousand stations of a large cell differ in numbers and
    names, so most of their lines are a shape already parsed from the same state."""

    def __init__(self, parser: Lark) -> None:
        table = tables(parser)
        self.states = table.states
        self.start_state = table.start_state
        self.end_state = table.end_state
        self.lexers = table.lexers  # parser state -> the terminals it accepts, as lark lexes them
        self.after: dict[tuple, tuple | None] = {}  # (stack, chunk shape) -> stack after it, None: rejected

    def accepts(self, text: str) -> bool:
        """True when lark would parse the whole text; False when it would not, or may not."""
        stack: tuple = (self.start_state,)
        after = self.after
        if len(after) > MEMO_MAX:
            after.clear()
        start = 0
        ends = [m.end() for m in CHUNK_END.finditer(text)]
        if not ends or ends[-1] != len(text):
            ends.append(len(text))
        for end in ends:
            shape = text[start:end].translate(DIGITS_AS_ZERO)
            key = (stack, shape)
            if key not in after:
                after[key] = self._chunk(list(stack), shape)
            stack = after[key]
            if stack is None:
                return False
            start = end
        return self._feed(list(stack), "$END", end=True)

    def _chunk(self, stack: list, chunk: str) -> tuple | None:
        """The stack after lexing and parsing one chunk from `stack`, None if lark would refuse it."""
        lex_state = lexer_state(chunk)
        while True:
            try:
                token = self.lexers[stack[-1]].next_token(lex_state)
            except EOFError:
                return tuple(stack)
            except UnexpectedCharacters:
                return None
            if not self._feed(stack, token.type):
                return None

    def _feed(self, stack: list, terminal: str, end: bool = False) -> bool:
        """Shift a terminal after the reductions it calls for (lark's feed_token without values); at the
        end ($END), reduce until the start rule is complete."""
        states = self.states
        while True:
            action = states[stack[-1]].get(terminal)
            if action is None:
                return False
            shift, arg = action
            if shift:
                if end:
                    return False
                stack.append(arg)
                return True
            size, rule = arg
            if size:
                del stack[-size:]
            stack.append(states[stack[-1]][rule][1])
            if end and stack[-1] == self.end_state:
                return True
