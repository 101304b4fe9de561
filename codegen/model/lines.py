"""Where a key path of a cell file lies in its TOML text: the line a message about the key names."""

from __future__ import annotations

import json
import re
import tomllib

_BARE = r"[A-Za-z0-9_-]+"
_QUOTED = r"\"(?:[^\"\\]|\\.)*\"|'[^']*'"
_NAME = rf"(?:{_BARE}|{_QUOTED})"
_DOTTED = rf"{_NAME}(?:\s*\.\s*{_NAME})*"
_HEADER = re.compile(rf"^\s*(\[\[?)\s*({_DOTTED})\s*\]\]?\s*(?:#.*)?$")
_KEY = re.compile(rf"^\s*({_DOTTED})\s*=")
_PART = re.compile(rf"\s*({_NAME})\s*")
_PATH_PART = re.compile(r"([^.\[\]]+)|\[(\d+)\]")


def line_of(text: str, path: str) -> int | None:
    """The line (from 1) of the key a message names (e.g. cell.limits.max_shift_mm), or of its nearest
    enclosing key or table the text writes out (a key inside an inline table: the line of the table); None when
    none is found."""
    where = key_lines(text)
    parts = _path_parts(path)
    for end in range(len(parts), 0, -1):
        line = where.get(tuple(parts[:end]))
        if line is not None:
            return line
    return None


def written(text: str, path: str) -> bool:
    """Whether the TOML text gives the key path at all (a key it leaves out takes its default); True where the
    text does not parse (its own error says more)."""
    try:
        node = tomllib.loads(text)
    except (tomllib.TOMLDecodeError, RecursionError):
        return True
    for part in _path_parts(path):
        if isinstance(node, dict) and isinstance(part, str):
            if part not in node:
                return False
            node = node[part]
        elif isinstance(node, list) and isinstance(part, int):
            if part >= len(node):
                return False
            node = node[part]
        else:
            return True
    return True


def key_lines(text: str) -> dict[tuple, int]:
    """Each table header's and key's path -> its first line: (name, ..., index of an array of tables, ...); an array
    of tables' own path (("station",)) -> its first entry's header. Values spanning lines (arrays, multi-line
    strings) are skipped over."""
    out: dict[tuple, int] = {}
    current: tuple = ()
    last: dict[tuple, int] = {}  # an array of tables' path -> the index of its last table so far
    depth = 0  # the brackets and braces a multi-line value leaves open
    in_string = ""  # the quotes of a multi-line string the line is in
    for number, line in enumerate(text.splitlines(), start=1):
        if in_string:
            if line.count(in_string) % 2:
                in_string = ""
            continue
        if depth == 0:
            header = _HEADER.match(line)
            if header:
                whole, current = _table_path(_names(header.group(2)), header.group(1) == "[[", last)
                out.setdefault(whole, number)
                out.setdefault(current, number)
                continue
            key = _KEY.match(line)
            if key:
                out.setdefault(current + tuple(_names(key.group(1))), number)
        depth, in_string = _scan(line, depth)
    return out


def _table_path(names: list[str], array: bool, last: dict[tuple, int]) -> tuple[tuple, tuple]:
    """A header's path without and with its entry's index (the same for a plain table), each array of tables it
    passes through at its last entry so far ([station.poses])."""
    path: tuple = ()
    for name in names[:-1]:
        path += (name,)
        if path in last:
            path += (last[path],)
    path += (names[-1],)
    if array:
        last[path] = last.get(path, -1) + 1
        out_of_array = path
        path += (last[path],)
        return out_of_array, path
    return path, path


def _names(dotted: str) -> list[str]:
    out = []
    for match in _PART.finditer(dotted):
        out.append(_unquoted(match.group(1)))
    return out


def _unquoted(name: str) -> str:
    """A key as TOML reads it: a literal string's text as written, a basic string's escapes resolved (those JSON
    shares with TOML; another is kept as written)."""
    if name[:1] == "'":
        return name[1:-1]
    if name[:1] != '"':
        return name
    try:
        return json.loads(name)
    except ValueError:
        return name[1:-1]


def _scan(line: str, depth: int) -> tuple[int, str]:
    """The bracket depth after a line (strings and comments skipped) and the quotes of a multi-line string it
    opens."""
    i = 0
    while i < len(line):
        char = line[i]
        if line.startswith(('"""', "'''"), i):
            end = line.find(line[i : i + 3], i + 3)
            if end < 0:
                return depth, line[i : i + 3]
            i = end + 3
            continue
        if char in "\"'":
            i += 1
            while i < len(line) and line[i] != char:
                i += 2 if char == '"' and line[i] == "\\" else 1
        elif char == "#":
            break
        elif char in "[{":
            depth += 1
        elif char in "]}":
            depth -= 1
        i += 1
    return max(depth, 0), ""


def _path_parts(path: str) -> list:
    parts: list = []
    for match in _PATH_PART.finditer(path):
        name, index = match.groups()
        if name is not None:
            parts.append(name)
        else:  # every array counts from 0 in messages, as in TOML's and JSON's own tools
            parts.append(int(index))
    return parts
