"""The one module that reaches into lark's internals: its LALR parser's tree callbacks, parse table and lexers."""

from __future__ import annotations

import fcntl
import hashlib
import os
import sys
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import lark
from lark import Lark, Token, Tree
from lark.lexer import LexerState
from lark.parsers.lalr_analysis import Shift
from lark.utils import TextSlice

# What this module relies on, by lark's own names (tests/dialects/core/test_larkdoor.py checks each against the
# installed lark; pyproject.toml bounds lark to the minor versions where they hold):
#   Lark.parser                      the ParsingFrontend; .lexer.lexers: parser state -> its contextual lexer
#   Lark.parser.parser.parser        the LALR _Parser: .callbacks (rule -> tree builder), .parse_table
#   parse_table.states / start_states / end_states, actions as (Shift, state) or (Reduce, rule)
#   rule.expansion, rule.origin.name
#   Tree._meta (None until lark or we set it), LexerState(TextSlice(...)), lexer.next_token(state)


def open_cached(grammar_file: str, rel_to: str, **options) -> Lark:
    """Lark.open of an LALR grammar, its analysed tables kept on disk through lark's own cache option (a build takes
    0.1-0.25 CPU s a grammar, a load a tenth of that, in every process that parses). lark keys the file by the
    grammar's text, the files it imports and its options, and rebuilds (and writes again) a parser whose file is
    stale, unreadable or corrupt; a lock beside the file keeps a process from reading it while another writes it.
    Without a private cache directory the parser is built every time."""
    folder = cache_dir()
    if folder is None:
        return Lark.open(grammar_file, rel_to=rel_to, **options)
    postlex = options.get("postlex")
    name = f"{Path(rel_to).resolve().parent}/{grammar_file}|{type(postlex).__qualname__}|{lark.__version__}"
    name += f"|{sys.version_info[:2]}|{sorted((k, repr(v)) for k, v in options.items() if k != 'postlex')}"
    cached = folder / f"{Path(rel_to).parent.name}-{hashlib.sha256(name.encode()).hexdigest()[:16]}.lark"
    with open(cached.with_suffix(".lock"), "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        return Lark.open(grammar_file, rel_to=rel_to, cache=str(cached), **options)


def cache_dir() -> Path | None:
    """The user's own directory for the parser tables ($XDG_CACHE_HOME/codegen/lark, else ~/.cache/codegen/lark, else
    one in the temporary directory), created private; None where none can be made or one is open to other users
    (a cache file is a pickle: loading it runs what it says)."""
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    for folder in (Path(base) / "codegen" / "lark", Path(tempfile.gettempdir()) / f"codegen-lark-{os.getuid()}"):
        try:
            folder.mkdir(mode=0o700, parents=True, exist_ok=True)
            status = folder.stat()
        except OSError:
            continue
        if status.st_uid == os.getuid() and not status.st_mode & 0o022 and os.access(folder, os.W_OK):
            return folder
    return None


class Start:
    """Where a tree starts: the part of lark's Meta the interpreter reads, in a quarter of the memory."""

    __slots__ = ("column", "container_column", "container_line", "line")
    empty = False

    def __init__(self, line: int, column: int) -> None:
        self.line = self.container_line = line
        self.column = self.container_column = column


def start_positions(build: Callable) -> Callable:
    """A tree-building callback that also sets where its tree starts, as lark's propagate_positions does
    (a tree starts where its first child's text does: a token, or a tree's container, which for a rule
    inlined into its child is where the rule's text began), without the ends lark also works out (a
    third of the cost: a 1,000-station program loads seconds faster)."""

    def with_start(children):
        tree = build(children)
        if type(tree) is Tree:
            for child in children:
                if type(child) is Token:
                    line, column = child.line, child.column
                    break
                if type(child) is Tree and child._meta is not None and not child._meta.empty:
                    line, column = child._meta.container_line, child._meta.container_column
                    break
            else:
                return tree
            meta = tree._meta
            if meta is None:
                tree._meta = Start(line, column)
            else:  # a rule inlined into its child: the child keeps its start, its container starts here
                meta.container_line, meta.container_column = line, column
        return tree

    return with_start


def mark_starts(parser: Lark) -> None:
    """Make an LALR parser (built without propagate_positions) give each tree the line and column where it
    starts (tree.meta.line, .column), by wrapping the callbacks that build its trees, rule by rule."""
    lalr = parser.parser.parser.parser
    lalr.callbacks = {rule: start_positions(build) for rule, build in lalr.callbacks.items()}


@dataclass(frozen=True)
class Tables:
    """An LALR parser's table and contextual lexers, for a parse without lark's parser loop."""

    # parser state -> {terminal or rule name: (True, next state) to shift, or (False, (size, rule name)) to reduce
    # by a rule of that many symbols}
    states: dict[int, dict[str, tuple]]
    start_state: int
    end_state: int
    # parser state -> the lexer of the terminals it accepts: .next_token(lexer_state(text)) gives the next token,
    # raises EOFError at the end of the text and lark.exceptions.UnexpectedCharacters where no terminal matches
    lexers: dict


def tables(parser: Lark) -> Tables:
    """The table and lexers of an LALR parser with the contextual lexer (lark's default for LALR)."""
    frontend = parser.parser
    table = frontend.parser.parser.parse_table
    start = parser.options.start[0]
    states = {
        state: {
            name: (True, arg) if kind is Shift else (False, (len(arg.expansion), arg.origin.name))
            for name, (kind, arg) in actions.items()
        }
        for state, actions in table.states.items()
    }
    return Tables(states, table.start_states[start], table.end_states[start], frontend.lexer.lexers)


def lexer_state(text: str) -> LexerState:
    """A fresh lexing position at the start of `text`, for a lexer of Tables.lexers."""
    return LexerState(TextSlice(text, 0, len(text)))


def terminals(parser: Lark) -> list[tuple[str, str, bool]]:
    """Each terminal of the grammar: (name, its regular expression, whether the lexer skips it). Read from the lexer's
    configuration, which a parser built from its grammar and one loaded from the cache both have (a loaded one has no
    `ignore_tokens`)."""
    ignored = set(parser.lexer_conf.ignore)
    return [(t.name, t.pattern.to_regexp(), t.name in ignored) for t in parser.lexer_conf.terminals]
