"""lark's internals that codegen/dialects/core/larkdoor.py relies on are still there, and still mean the same."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedCharacters
from packaging.requirements import Requirement
from packaging.version import Version

from codegen.dialects.core import larkdoor

ROOT = Path(__file__).resolve().parents[3]

# A grammar small enough to know its table by hand: `a = 1 + 2` lines
GRAMMAR = r"""
start: line+
line: NAME "=" sum _NL
?sum: atom | sum "+" atom
?atom: NUMBER | NAME
NAME: /[a-z]+/
NUMBER: /[0-9]+/
_NL: /\n/
%ignore " "
"""


def _parser(**options) -> Lark:
    return Lark(GRAMMAR, parser="lalr", **options)


def _dependency(name: str) -> Requirement:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    return next(r for r in map(Requirement, project["dependencies"]) if r.name == name)


def test_installed_lark_is_within_the_pinned_minor():
    import lark

    requirement = _dependency("lark")
    assert Version(lark.__version__) in requirement.specifier, (lark.__version__, str(requirement))
    upper = next(s for s in requirement.specifier if s.operator == "<")
    assert len(Version(upper.version).release) >= 2, "lark's internals move between minor versions: pin the minor"


def test_the_lalr_callbacks_build_the_trees_rule_by_rule():
    parser = _parser()
    lalr = parser.parser.parser.parser
    assert isinstance(lalr.callbacks, dict) and lalr.callbacks
    assert all(callable(build) for build in lalr.callbacks.values())
    seen = []

    def noting(build, name):
        return lambda children: seen.append(name) or build(children)

    lalr.callbacks = {rule: noting(build, rule.origin.name) for rule, build in lalr.callbacks.items()}
    parser.parse("a = 1 + b\n")
    assert {"line", "sum", "start"} <= set(seen)


def test_trees_carry_their_meta_in_meta_underscore():
    tree = _parser().parse("a = 1\n")
    assert tree._meta is None  # built without positions: lark has not made one
    assert tree.meta.empty  # the public property makes an empty one on demand
    assert tree._meta is not None


def test_marked_starts_are_larks_positions():
    ours = _parser()
    larkdoor.mark_starts(ours)
    theirs = _parser(propagate_positions=True)
    text = "a = 1\n  bc = d + 22\nx = y\n"
    pairs = list(zip(ours.parse(text).iter_subtrees(), theirs.parse(text).iter_subtrees(), strict=True))
    assert len(pairs) == 5
    for mine, reference in pairs:
        assert mine.data == reference.data
        assert (mine.meta.line, mine.meta.column) == (reference.meta.line, reference.meta.column)
    assert [(t.meta.line, t.meta.column) for t, _ in pairs if t.data == "line"] == [(1, 1), (2, 3), (3, 1)]


def test_tables_shift_and_reduce_as_the_grammar_says():
    table = larkdoor.tables(_parser())
    first = table.states[table.start_state]
    assert first["NAME"][0] is True  # a line starts with a name: shift
    after_name = table.states[first["NAME"][1]]
    assert set(after_name) == {"EQUAL"}
    reduces = [arg for shift, arg in (a for actions in table.states.values() for a in actions.values()) if not shift]
    assert (4, "line") in reduces  # line: NAME "=" sum _NL, four symbols
    assert (3, "sum") in reduces
    assert table.end_state in table.states and table.end_state != table.start_state


def test_contextual_lexers_lex_from_a_lexer_state():
    table = larkdoor.tables(_parser())
    lexer = table.lexers[table.start_state]
    state = larkdoor.lexer_state("ab = 7\n")
    token = lexer.next_token(state)
    assert isinstance(token, Token) and (token.type, str(token)) == ("NAME", "ab")
    assert table.lexers[table.states[table.start_state]["NAME"][1]].next_token(state).type == "EQUAL"
    with pytest.raises(EOFError):
        lexer.next_token(larkdoor.lexer_state(""))
    with pytest.raises(UnexpectedCharacters):
        lexer.next_token(larkdoor.lexer_state("?"))


def test_terminals_describe_their_patterns():
    """parsing.syntax_error spells a terminal from its pattern's type, value and flags (Lark.terminals)."""
    patterns = {t.name: t.pattern for t in _parser().terminals}
    assert (patterns["EQUAL"].type, patterns["EQUAL"].value) == ("str", "=")
    assert (patterns["NAME"].type, patterns["NAME"].value) == ("re", "[a-z]+")
    assert isinstance(patterns["NAME"].flags, tuple | list | frozenset | set)


def test_a_tree_is_larks_tree():
    assert type(_parser().parse("a = 1\n")) is Tree
