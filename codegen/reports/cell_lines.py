"""A cell file's array-of-tables entry a verify case names, and the key under it (its lines: codegen.model.lines)."""

from __future__ import annotations

import re


def entry_of(data: dict, words: str) -> tuple[str, int] | None:
    """The array-of-tables entry (("station", 0)) a text names as "<table> <id>" or "<table> <name>" (a case's
    description: "station 3 reading ..."), where exactly one does."""
    found = []
    for table, entries in data.items():
        if not isinstance(entries, list):
            continue
        for index, entry in enumerate(entries):
            if not isinstance(entry, dict):
                continue
            for field in ("id", "name"):
                value = entry.get(field)
                if value is not None and re.search(rf"\b{re.escape(table)} {re.escape(str(value))}\b", words):
                    found.append((table, index))
                    break
    return found[0] if len(set(found)) == 1 else None


def key_under(lines: dict[tuple, int], prefix: tuple, name: str, data: dict | None = None) -> tuple | None:
    """The one key path below prefix whose last key is name (None: none, or several). Given the file's data, a
    move's name: the one that holds an array (a pose's values; a key of the same name that says what happens there,
    a gripper's "grip", is not where it is taught)."""
    found = [path for path in lines if path[: len(prefix)] == prefix and path[-1] == name and len(path) > len(prefix)]
    if data is not None:
        found = [path for path in found if isinstance(_value(data, path), list)]
    return found[0] if len(found) == 1 else None


def _value(data: dict, path: tuple):
    value = data
    for part in path:
        try:
            value = value[part]
        except (KeyError, IndexError, TypeError):
            return None
    return value
