"""A starter cell file per program kind: the smallest bundled example of the kind, for the targets asked."""

from __future__ import annotations

import re
import tomllib
from collections.abc import Callable, Iterator
from pathlib import Path

from codegen.model.cell import EXAMPLES_DIR

_SCHEMA_LINE = re.compile(r"^#:schema .*\n")
_KEY = re.compile(r"^\s*([A-Za-z0-9_]+)\s*=")
_TARGETS = re.compile(r"^(targets\s*=\s*)\[[^\]]*\]", re.M)


class StarterError(Exception):
    """No starter for what was asked (the message says why)."""


def example_of(tables: frozenset[str]) -> Path:
    """The bundled example cell of the kind (its top-level tables include one of the kind's) written for the most
    targets, the smallest of those."""
    found = []
    for path in sorted(EXAMPLES_DIR.rglob("*.toml")):
        text = path.read_text(encoding="utf-8")
        data = tomllib.loads(text)
        if isinstance(data.get("cell"), dict) and tables & set(data):
            found.append((-len(data["cell"].get("targets", ())), len(text), str(path), path))
    if not found:
        raise StarterError("no bundled example cell of this kind")
    return min(found)[3]


def starter_text(
    example: Path, chosen: tuple[str, ...], all_targets: tuple[str, ...], trim: Callable[[str], str] | None = None
) -> str:
    """The example's text (trimmed by the kind's `trim`, e.g. to one of its modes) for the chosen targets (all the
    example's when none is chosen): the targets line, and every other target's entries left out (its own lines, its
    items of inline tables). Comments stay."""
    text = _SCHEMA_LINE.sub("", example.read_text(encoding="utf-8"), count=1)
    if trim is not None:
        text = trim(text)
    listed = tuple(tomllib.loads(text)["cell"]["targets"])
    unknown = [t for t in chosen if t not in listed]
    if unknown:
        raise StarterError(f"--target {unknown[0]}: the starter is written for {', '.join(listed)}")
    if not chosen:
        return text
    dropped = set(all_targets) - set(chosen)
    kept = [t for t in listed if t in chosen]
    lines = []
    for line in text.splitlines():
        match = _KEY.match(line)
        if match and match.group(1) in dropped:
            continue  # a target's own line (e.g. [cell.robot] ur = "...")
        line = _without(line, dropped)
        if line is not None:
            lines.append(line)
    out = "\n".join(lines) + "\n"
    return _TARGETS.sub(lambda m: m.group(1) + "[" + ", ".join(f'"{t}"' for t in kept) + "]", out, count=1)


def _without(line: str, dropped: set[str]) -> str | None:
    """The line with the dropped targets' items taken out of its inline tables; None where an inline table of
    targets is left empty (the key is then for the dropped targets alone)."""
    start = line.find("{")
    if start < 0 or line.lstrip().startswith("#"):
        return line
    end = _closing(line, start)
    items = _items(line[start + 1 : end])
    kept = [item for item in items if _KEY.match(item) is None or _KEY.match(item).group(1) not in dropped]
    if len(kept) == len(items):
        return line
    if not kept:
        return None
    shortened = line[:start] + "{ " + ", ".join(item.strip() for item in kept) + " }"
    rest = line[end + 1 :]
    comment = rest.lstrip()
    if comment.startswith("#"):  # the comment stays in its column, in line with its neighbours' as written
        rest = " " * (end + 1 + len(rest) - len(comment) - len(shortened)) + comment
    return shortened + rest


def _closing(line: str, start: int) -> int:
    for i, c, depth, quoted in _scan(line, start):
        if not quoted and c in "}]" and depth == 0:
            return i
    raise StarterError(f"an inline table not closed on its line: {line.strip()}")


def _items(body: str) -> list[str]:
    """An inline table's items, split at the commas outside brackets and strings."""
    items, current = [], ""
    for _i, c, depth, quoted in _scan(body):
        if c == "," and depth == 0 and not quoted:
            items.append(current)
            current = ""
        else:
            current += c
    if current.strip():
        items.append(current)
    return items


def _scan(text: str, start: int = 0) -> Iterator[tuple[int, str, int, bool]]:
    """Each character from start with the bracket depth and whether it is in a string, once it is read: (index,
    character, depth, quoted)."""
    depth, quoted = 0, False
    for i in range(start, len(text)):
        c = text[i]
        if c == '"':
            quoted = not quoted
        elif not quoted and c in "{[":
            depth += 1
        elif not quoted and c in "}]":
            depth -= 1
        yield i, c, depth, quoted
