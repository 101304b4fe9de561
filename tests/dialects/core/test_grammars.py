"""The grammars' shared terminals (codegen/dialects/core/terminals.lark): defined once, read alike by lark and by us."""

from __future__ import annotations

import re

import pytest

from codegen.dialects import SHARED_TERMINALS, dialects
from codegen.dialects.core.parsing import open_grammar

GRAMMARS = sorted(name for name, dialect in dialects().items() if dialect._grammar().exists())
PATTERN = re.compile(r"^(_?[A-Z][A-Z_0-9]*): /(.*)/$", re.MULTILINE)
ESCAPED = str.maketrans({"\n": "\\n", "\t": "\\t", "\f": "\\f", "\r": "\\r"})  # lark unescapes these


def _interpreter(name: str) -> str:
    return dialects()[name].module("interpreter").__file__


def test_every_grammar_is_found():
    assert GRAMMARS == ["dtrans", "krl", "rapid", "urscript"]


@pytest.mark.parametrize("name", GRAMMARS)
def test_no_grammar_restates_a_shared_terminal(name):
    """Neither a shared terminal's pattern (under any name, or as an %ignore) nor its name with the same meaning."""
    shared = dict(PATTERN.findall(SHARED_TERMINALS.read_text(encoding="utf-8")))
    assert set(shared) == {"INT", "STRING", "_NL", "WS_INLINE"}
    text = dialects()[name]._grammar().read_text(encoding="utf-8")
    for terminal, pattern in shared.items():
        assert f"/{pattern}/" not in text, terminal


@pytest.mark.parametrize("name", GRAMMARS)
def test_a_dialects_terminals_are_larks(name):
    """Dialect.terminal (what emit.py reads a language's strings and comments by) gives the pattern lark
    compiled, imported terminals included."""
    dialect = dialects()[name]
    compiled = {t.name: t.pattern for t in open_grammar(_interpreter(name)).terminals}
    read = 0
    for terminal, pattern in compiled.items():
        ours = dialect.terminal(terminal)
        if ours is not None:
            assert pattern.type == "re" and ours == pattern.value.translate(ESCAPED), terminal
            read += 1
    assert dialect.terminal("STRING") == compiled["STRING"].value.translate(ESCAPED)
    assert read >= 3


def test_the_shared_terminals_reach_the_grammars_that_import_them():
    imported = {
        name: {t.name for t in open_grammar(_interpreter(name)).terminals} & {"INT", "STRING", "_NL", "WS_INLINE"}
        for name in GRAMMARS
    }
    assert imported == {
        "dtrans": {"INT", "STRING", "_NL", "WS_INLINE"},
        "krl": {"INT", "STRING", "_NL", "WS_INLINE"},
        "rapid": {"STRING"},  # its own: doubled quotes and \\hh escapes
        "urscript": {"STRING", "_NL", "WS_INLINE"},
    }
