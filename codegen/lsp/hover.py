"""Hover texts: a name's declaration, a motion line's pose and joints in the nominal run, a cell key's reference."""

from __future__ import annotations

import re

from lsprotocol import types

from codegen.decimals import unsigned_zero
from codegen.lsp import cellschema
from codegen.lsp.documents import Program
from codegen.lsp.nominal import Move
from codegen.lsp.symbols import definitions, folded, word_at


def shown(text: str, kind: types.MarkupKind) -> types.Hover:
    """A hover of Markdown text, as Markdown where the client reads it, else as the same text, plain."""
    return types.Hover(contents=types.MarkupContent(kind=kind, value=text))


def symbol_text(program: Program, path: str, line: int, character: int) -> str | None:
    """A name's declaration (its line, which gives its type) and where it is, or what the controller has of it."""
    found = word_at(program.text_of(path) or "", line, character)
    if found is None:
        return None
    name, _start = found
    language = program.dialect.name
    out = []
    for symbol in definitions(program, name)[:3]:
        text = program.text_of(symbol.file) or ""
        declared = text.split("\n")[symbol.line - 1].strip()
        where = symbol.file.rsplit("/", 1)[-1]
        scope = "" if symbol.top else " (local)"
        fence = "`" * max(3, 1 + max((len(run) for run in re.findall(r"`+", declared)), default=0))
        out.append(f"{fence}{language}\n{declared}\n{fence}\n{symbol.kind.name.lower()}{scope}, {where}:{symbol.line}")
    if not out and folded(program.dialect, name) in program.dialect.predefined():
        out.append(f"`{name}`: predefined by the controller ({language})")
    return "\n\n---\n\n".join(out) or None


def move_text(moves: list[Move]) -> str:
    """What the moves at one line command in the nominal run: the pose (the target's format) and the arm's joints."""
    parts = []
    for i, move in enumerate(moves[:3]):
        pose = "a joint position" if move.pose is None else " ".join(unsigned_zero(f"{v:.3f}") for v in move.pose)
        joints = "" if move.joints is None else " ".join(unsigned_zero(f"{v:.2f}") for v in move.joints)
        head = f"**{move.kind} move** in the nominal run" + (f" (pass {i + 1})" if len(moves) > 1 else "")
        shown = f"{head}\n\npose ({move.pose_format}): `{pose}`"
        parts.append(shown + (f"\n\njoints (deg): `{joints}`" if joints else ""))
    if len(moves) > 3:
        parts.append(f"... and {len(moves) - 3} more passes")
    return "\n\n".join(parts)


def cell_text(text: str, line: int) -> str | None:
    """The reference of the key (or table) a cell file's line writes (0-based line)."""
    path = cellschema.path_of_line(text, line + 1)
    if path is None:
        return None
    node = cellschema.definition_at(path)
    return None if node is None else cellschema.describe(path, node)
