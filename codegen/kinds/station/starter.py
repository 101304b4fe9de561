"""The starter of one station mode: the kind's bundled example with the other modes' stations and tables left out."""

from __future__ import annotations

import re
import tomllib

from codegen.kinds.station.keys import default_mode
from codegen.kinds.station.mode import modes

_HEADER = re.compile(r"^\s*\[\[?\s*([A-Za-z0-9_.]+)\s*\]\]?\s*(#.*)?$")
_NAME = re.compile(r'^(name\s*=\s*)"([^"]*)"', re.M)
HANDEYE = "cell.camera.handeye"  # the table of a camera that answers in pixels (StationMode.reads_pixels)


def _segments(text: str) -> list[tuple[str | None, list[str]]]:
    """The text cut at its table headers: (the header's table name, or None before the first, its lines)."""
    out: list[tuple[str | None, list[str]]] = [(None, [])]
    for line in text.splitlines():
        match = _HEADER.match(line)
        if match:
            out.append((match.group(1), []))
        out[-1][1].append(line)
    return out


def mode_starter(text: str, mode: str) -> str:
    """The example's text with only the stations of `mode` (the others' [[station]] tables and their sub-tables
    left out), without the [cell.<table>] tables of the modes left out, and the cell named after the mode. Comments
    inside a table that is left out go with it."""
    registered = modes()
    data = tomllib.loads(text)
    kept_modes = [s.get("mode", default_mode()) for s in data.get("station", [])]
    if mode not in kept_modes:
        raise ValueError(f"the example has no {mode} station")
    dropped_tables = {
        f"cell.{table}"
        for name, cls in registered.items()
        if name != mode and cls.cell_file is not None
        for table in cls.cell_file.cell_tables
    }
    if not registered[mode].reads_pixels:
        dropped_tables.add(HANDEYE)
    lines: list[str] = []
    station = -1
    for table, body in _segments(text):
        if table == "station":
            station += 1
        in_station = table is not None and (table == "station" or table.startswith("station."))
        if in_station and kept_modes[station] != mode:
            continue
        if table in dropped_tables or any(table is not None and table.startswith(t + ".") for t in dropped_tables):
            continue
        lines.extend(body)
    out = "\n".join(lines) + "\n"
    return _NAME.sub(lambda m: f'{m.group(1)}"{m.group(2)}_{mode}"', out, count=1)
