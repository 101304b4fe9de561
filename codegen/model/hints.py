"""What a missing key of a cell file is for, with a minimal example of it, from the cell file's definition."""

from __future__ import annotations

import re

from codegen.model.schema import Key, Table

_INDEX = re.compile(r"\[\d+\]")
EXAMPLE_KEYS = 3  # a table with no required key: its first few keys shown


def missing_hint(root: Table, key_path: str, targets: tuple[str, ...] = ()) -> tuple[str, str]:
    """The definition's words for the key at key_path (e.g. "cell.limits", "station[1].mark") and a minimal
    example of it (its required keys with their units and ranges; a value per controller for the cell's targets);
    ("", "") where the definition has no such key."""
    names = _INDEX.sub("", key_path).split(".")
    table: Table | None = root
    key: Key | None = None
    for name in names:
        if table is None or name not in table.keys:
            return "", ""
        key = table.keys[name]
        table = key.table
    if key is None:
        return "", ""
    doc = key.table.doc if key.table is not None else key.doc
    return doc.rstrip("."), _example(key, names, targets)


def _example(key: Key, names: list[str], targets: tuple[str, ...]) -> str:
    if key.table is None:
        return f"    {names[-1]} = {_value(key, targets).split('  # ', 1)[0]}"  # its words are said before
    header = f"[[{'.'.join(names)}]]" if key.type == "tables" else f"[{'.'.join(names)}]"
    shown = [n for n, k in key.table.keys.items() if k.required] or list(key.table.keys)[:EXAMPLE_KEYS]
    lines = [f"    {header}"] + [f"    {n} = {_value(key.table.keys[n], targets)}" for n in shown]
    return "\n".join(lines)


def _value(key: Key, targets: tuple[str, ...] = ()) -> str:
    """A value of the key as the file writes it: its default, else what it takes (type, unit, range) in < >; a value
    per controller (a signal) for each of the cell's targets that has one (none known: every controller's)."""
    if key.default is not None and not isinstance(key.default, dict):
        return _written(key.default)
    if key.choices:
        return _written(key.choices[0])
    if key.type == "map" and key.per_name:
        shown = [t for t in targets if t in key.per_name] or list(key.per_name)
        return "{ " + ", ".join(f"{t} = {_value(key.per_name[t]).split('  # ', 1)[0]}" for t in shown) + " }"
    if key.type == "table" or key.type == "map":
        return "{ ... }"
    if key.type == "string":
        return '"..."'
    what = key.unit or key.type
    if key.type in ("numbers", "pose") and isinstance(key.count, int):
        return "[" + ", ".join([f"<{key.unit or 'number'}>"] * key.count) + "]" + (f"  # {key.doc}" if key.doc else "")
    if key.type == "list":
        return f"[<{key.values.doc if key.values is not None else 'a value'}>]"
    span = key.range_text()
    return f"<{what}{' ' + span if span else ''}>" + (f"  # {key.doc}" if key.doc else "")


def _written(value) -> str:
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, tuple | list):
        return "[" + ", ".join(_written(v) for v in value) + "]"
    return f"{value:g}" if isinstance(value, float) else str(value)
