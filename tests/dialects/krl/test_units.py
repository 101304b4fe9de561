"""A KRL file parsed routine by routine (codegen/dialects/krl/syntax.py) gives the tree lark gives the whole text, and
the whole text's syntax error where it has one."""

from __future__ import annotations

import random
from pathlib import Path

import pytest
from lark import Token, Tree

from codegen.dialects.core.kept import STORE
from codegen.dialects.core.parsing import _parse
from codegen.dialects.core.values import RunError
from codegen.dialects.krl.syntax import INTERPRETER, parse

ROOT = Path(__file__).resolve().parents[3]
FILES = sorted(p for p in (ROOT / "generated").rglob("*") if p.suffix.lower() in (".src", ".dat"))
EDITS = ("END", "DEF X()", "ENDIF", "DEFDAT Y", "ENDDAT", "  GLOBAL DEF Z()", "ENDFCT", "x", "DEFFCT INT F()")


def shape(node):
    """A tree as data, every token's type, text, line and column and every tree's start (Token's == is its text's)."""
    if isinstance(node, Token):
        return ("token", node.type, str(node), node.line, node.column)
    if isinstance(node, Tree):
        meta = node._meta
        start = (
            None if meta is None or meta.empty else (meta.line, meta.column, meta.container_line, meta.container_column)
        )
        return (node.data, start, [shape(child) for child in node.children])
    return node


def whole(text: str, name: str):
    """lark's parse of the whole text, or its syntax error's message."""
    try:
        return shape(_parse(INTERPRETER, text, name, None, True))
    except RunError as exc:
        return str(exc)


def units(text: str, name: str):
    """The tree as parse gives it while the store keeps trees: routine by routine."""
    with STORE.keeping():
        try:
            return shape(parse(text, name))
        except RunError as exc:
            return str(exc)


def test_there_are_files_of_several_routines():
    assert len(FILES) >= 10
    assert any(sum(line.startswith(("DEF ", "GLOBAL DEF ")) for line in p.read_text().split("\n")) > 3 for p in FILES)


@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(ROOT / "generated")))
def test_a_generated_file_parses_as_a_whole(path: Path):
    text = path.read_text(encoding="utf-8")
    assert units(text, path.name) == whole(text, path.name)


def test_edited_files_parse_or_fail_as_a_whole():
    """Lines deleted, cut, given a second `=`, or a routine's or data list's head or end put in: the same tree, or
    the same syntax error, as the whole text's."""
    rnd = random.Random(41)
    failed = 0
    for _ in range(150):
        path = rnd.choice(FILES)
        lines = path.read_text(encoding="utf-8").split("\n")
        i = rnd.randrange(len(lines))
        edit = rnd.randrange(4)
        if edit == 0:
            del lines[i]
        elif edit == 1:
            lines[i] = lines[i].replace("=", "= =", 1)
        elif edit == 2:
            lines.insert(i, rnd.choice(EDITS))
        else:
            lines[i] = lines[i][: len(lines[i]) // 2]
        text = "\n".join(lines)
        expected = whole(text, path.name)
        STORE.clear()
        assert units(text, path.name) == expected, (path.name, i, edit)
        failed += isinstance(expected, str)
    assert 20 < failed < 130  # both kinds were tried
