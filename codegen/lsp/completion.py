"""Completion: the controller's predefined names and the program's own; a cell file's keys from its definition."""

from __future__ import annotations

from lsprotocol import types

from codegen.lsp import cellschema
from codegen.lsp.documents import Program
from codegen.lsp.symbols import program_symbols

KIND = types.CompletionItemKind


def program_items(program: Program) -> list[types.CompletionItem]:
    """The program's declared names (with their declaration) and the controller's predefined names."""
    items: dict[str, types.CompletionItem] = {}
    for symbol in program_symbols(program):
        text = program.text_of(symbol.file) or ""
        detail = text.split("\n")[symbol.line - 1].strip()[:80]
        items.setdefault(symbol.name, types.CompletionItem(label=symbol.name, kind=KIND.Variable, detail=detail))
        if symbol.kind in (types.SymbolKind.Function, types.SymbolKind.Event):
            items[symbol.name].kind = KIND.Function
    for name in sorted(program.dialect.predefined()):
        items.setdefault(
            name, types.CompletionItem(label=name, kind=KIND.Keyword, detail=f"{program.dialect.name} predefined")
        )
    return list(items.values())


def cell_items(text: str, line: int, kind: types.MarkupKind = types.MarkupKind.Markdown) -> list[types.CompletionItem]:
    """The keys the table around a 0-based line may hold and it does not write yet, each with its reference."""
    table = cellschema.table_of_line(text, line + 1)
    written = {path[-1] for path in _paths(text) if path[: len(table)] == table and len(path) == len(table) + 1}
    keys = cellschema.keys_of(table) if table else cellschema.keys_of(())
    out = []
    for name, key in keys.items():
        if name in written or key is None:
            continue
        doc = cellschema.describe((*table, name), key)
        out.append(
            types.CompletionItem(
                label=name,
                kind=KIND.Property,
                detail=key.doc[:80],
                documentation=types.MarkupContent(kind=kind, value=doc),
                insert_text=f"{name} = ",
            )
        )
    return out


def _paths(text: str):
    from codegen.model.lines import key_lines

    return key_lines(text).keys()
