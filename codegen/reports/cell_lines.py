"""Where each key of a TOML cell file is written: its key path (array entries by index) -> line, read from the text
(tomllib gives values, not places)."""

from __future__ import annotations

import re

BARE = re.compile(r"[A-Za-z0-9_-]+")
BASIC = re.compile(r'"(?:[^"\\]|\\.)*"')
LITERAL = re.compile(r"'[^']*'")
OPENERS, CLOSERS = "[{", "]}"


def key_lines(text: str) -> dict[tuple, int]:
    """Every key's path (("station", 0, "poses", "chuck")) and the 1-based line it is written on; a table header's
    path maps to the header's line. Values spanning lines (arrays, multi-line strings) are skipped over."""
    out: dict[tuple, int] = {}
    counts: dict[tuple, int] = {}  # array-of-tables path -> entries so far
    table: tuple = ()
    depth, quote = 0, None  # inside a multi-line value: brackets open, or the multi-line string's quotes
    for number, line in enumerate(text.splitlines(), start=1):
        if quote is not None or depth:
            depth, quote = _scan(line, 0, depth, quote)
            continue
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        if stripped.startswith("["):
            many = stripped.startswith("[[")
            keys, _ = _keys(stripped, 2 if many else 1)
            if many:  # a new entry of the array: its last key counts, the ones before pass through their last
                path = (*_resolved(tuple(keys[:-1]), counts), *keys[-1:])
                counts[path] = counts.get(path, -1) + 1
                out.setdefault(path, number)
                path = (*path, counts[path])
            else:
                path = _resolved(tuple(keys), counts)
            table = path
            out.setdefault(table, number)
            continue
        keys, end = _keys(line, len(line) - len(line.lstrip()))
        if not keys or end >= len(line) or line[end] != "=":
            continue
        out.setdefault((*table, *keys), number)
        depth, quote = _scan(line, end + 1, 0, None)
    return out


def _resolved(keys: tuple, counts: dict[tuple, int]) -> tuple:
    """A header's dotted keys with each array of tables it passes through at its last entry ([station.poses])."""
    out: tuple = ()
    for key in keys:
        out = (*out, key)
        if out in counts:
            out = (*out, counts[out])
    return out


def _keys(text: str, i: int) -> tuple[list[str], int]:
    """The dotted key starting at text[i] and the index after it (and the spaces after it)."""
    keys = []
    while True:
        while i < len(text) and text[i] in " \t":
            i += 1
        for pattern, strip in ((BASIC, True), (LITERAL, True), (BARE, False)):
            match = pattern.match(text, i)
            if match:
                raw = match.group()
                keys.append(_unquoted(raw) if strip else raw)
                i = match.end()
                break
        else:
            return keys, i
        while i < len(text) and text[i] in " \t":
            i += 1
        if i < len(text) and text[i] == ".":
            i += 1
            continue
        return keys, i


def _unquoted(raw: str) -> str:
    if raw.startswith("'"):
        return raw[1:-1]
    import json

    try:
        return json.loads(raw)
    except ValueError:
        return raw[1:-1]


def _scan(line: str, i: int, depth: int, quote: str | None) -> tuple[int, str | None]:
    """Brackets still open and the multi-line string still open at the end of a value's line."""
    while i < len(line):
        if quote is not None:
            end = line.find(quote, i)
            if end < 0:
                return depth, quote
            i, quote = end + 3, None
            continue
        c = line[i]
        if c == "#":
            break
        if line.startswith(('"""', "'''"), i):
            quote, i = line[i : i + 3], i + 3
            continue
        if c in "\"'":
            match = (BASIC if c == '"' else LITERAL).match(line, i)
            i = match.end() if match else len(line)
            continue
        depth += (c in OPENERS) - (c in CLOSERS)
        i += 1
    return depth, quote


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


def key_under(lines: dict[tuple, int], prefix: tuple, name: str) -> tuple | None:
    """The one key path below prefix whose last key is name (None: none, or several)."""
    found = [path for path in lines if path[: len(prefix)] == prefix and path[-1] == name and len(path) > len(prefix)]
    return found[0] if len(found) == 1 else None
