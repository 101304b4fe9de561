"""The KRL parser: grammar.lark (beside interpreter.py, whose path keys the cached parser) to a lark tree."""

from __future__ import annotations

from pathlib import Path

from lark import Tree

from codegen.dialects.core.parsing import parse_with_grammar

INTERPRETER = str(Path(__file__).with_name("interpreter.py"))  # the cache key Dialect.parse and check use


def parse(text: str, filename: str = "<krl>", positions: bool = True) -> Tree:
    return parse_with_grammar(INTERPRETER, text, filename, positions)
