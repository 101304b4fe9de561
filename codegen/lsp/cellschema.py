"""The cell file's definition (codegen.model.schema) at a place of a cell file's text: the key a line writes, the
table a line is in, and what the reference says of a key."""

from __future__ import annotations

import re

from codegen.model import tables
from codegen.model.lines import key_lines
from codegen.model.schema import Key, Table
from codegen.protocol import installed_kinds

HEADER = re.compile(r"^\s*\[\[?")


def file_table() -> Table:
    return tables.file_table(installed_kinds())


def definition_at(path: tuple) -> Key | Table | None:
    """The Key (or, for a table's own path, its Table) a key path names: ("cell", "limits", "max_shift_mm"),
    ("station", 0, "poses", "approach"); None where the definition has no such key."""
    node: Key | Table = Key("table", file_table().doc, table=file_table())
    for part in path:
        if isinstance(node, Key) and node.type == "either":
            node = next((k for k in node.alternatives if k.type in ("table", "tables", "map")), node)
        if isinstance(node, Key) and node.type == "tables" and isinstance(part, int):
            node = Key("table", node.doc, table=node.table)
            continue
        if isinstance(part, int):
            return None
        table = node.table if isinstance(node, Key) and node.type in ("table", "tables") else None
        if table is not None:
            if part not in table.keys:
                return None
            node = table.keys[part]
        elif isinstance(node, Key) and node.type == "map":
            own = node.per_name.get(part, node.values)
            if own is None or (node.names is not None and part not in node.names):
                return None
            node = own
        else:
            return None
    return node


def path_of_line(text: str, line: int) -> tuple | None:
    """The key path written on `line` (from 1): a key's or a table header's; None where the line writes none."""
    return next((path for path, number in key_lines(text).items() if number == line and _written(path)), None)


def table_of_line(text: str, line: int) -> tuple:
    """The path of the table whose keys a line stands among: the last table header at or above it (() before any)."""
    best: tuple = ()
    best_line = 0
    lines = text.splitlines()
    for path, number in key_lines(text).items():
        header = best_line <= number <= min(line, len(lines)) and HEADER.match(lines[number - 1])
        if header and (number > best_line or len(path) > len(best)):
            best, best_line = path, number
    return best


def _written(path: tuple) -> bool:
    return bool(path) and not isinstance(path[-1], int)


def dotted(path: tuple) -> str:
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else part)
    return out


def describe(path: tuple, node: Key | Table) -> str:
    """A key's entry of the cell-file reference as Markdown: what it is, its unit, range, allowed values, default."""
    if isinstance(node, Table) or node.type in ("table", "tables"):
        table = node if isinstance(node, Table) else node.table
        keys = ", ".join(f"`{k}`" for k in table.keys) if table is not None else ""
        return f"**{dotted(path)}**: {node.doc}\n\nkeys: {keys}"
    facts = [f"type: {node.type}"]
    if node.unit:
        facts.append(f"unit: {node.unit}")
    if node.range_text():
        facts.append(f"range: {node.range_text()}")
    if node.choices:
        facts.append("one of: " + ", ".join(f"`{c}`" for c in node.choices))
    if node.default is not None:
        facts.append(f"default: `{node.default}`")
    if node.required:
        facts.append("required")
    if node.kinds:
        facts.append("used by: " + ", ".join(node.kinds))
    return f"**{dotted(path)}**: {node.doc}\n\n" + " · ".join(facts)


def keys_of(path: tuple) -> dict[str, Key]:
    """The keys a table (its path) may hold, by name; {} for a path that is no table."""
    node = definition_at(path)
    if isinstance(node, Key) and node.type == "either":
        node = next((k for k in node.alternatives if k.type == "table"), node)
    if isinstance(node, Key) and node.type in ("table", "tables") and node.table is not None:
        return dict(node.table.keys)
    if isinstance(node, Key) and node.type == "map" and node.names is not None:
        return {name: node.per_name.get(name, node.values) for name in node.names}
    return {}
