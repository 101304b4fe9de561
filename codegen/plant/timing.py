"""A cell's JSON in a plant's report split in two: what was found (the same bytes wherever, on however many workers and
however fast it ran) and how long it took."""

from __future__ import annotations

# The keys that tell how long a run took or how it was spread, never what it found: verify's report of a cell
# (verify.report.Report: wall_seconds, workers) and each of its rows (verify.report.Row.summary: seconds,
# cases_per_second, clearance_seconds; the kinds' rows made from them, ProgramKind.legacy_summary: cases_per_s),
# the plant's own rows (results.Line: seconds).
CELL_TIMES = ("wall_seconds", "workers")
ROW_TIMES = ("seconds", "cases_per_second", "cases_per_s", "clearance_seconds")


def split(data: dict | None) -> tuple[dict | None, dict]:
    """(data without its times, the times): the top level's CELL_TIMES, and ROW_TIMES of each row in a list at the
    top level; a list's times are listed in the list's order (an empty entry for a row without any)."""
    if data is None:
        return None, {}
    found, times = {}, {}
    for key, value in data.items():
        if key in CELL_TIMES:
            times[key] = value
        elif isinstance(value, list) and any(isinstance(row, dict) and _timed(row) for row in value):
            found[key] = [_without(row) for row in value]
            times[key] = [_only(row) for row in value]
        else:
            found[key] = value
    return found, times


def _timed(row: dict) -> bool:
    return any(key in row for key in ROW_TIMES)


def _without(row):
    return {k: v for k, v in row.items() if k not in ROW_TIMES} if isinstance(row, dict) else row


def _only(row) -> dict:
    return {k: v for k, v in row.items() if k in ROW_TIMES} if isinstance(row, dict) else {}
