"""Calibration CSV files, read one way: a regular UTF-8 file of bounded size, a fixed header, strict numbers."""

from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass
from pathlib import Path

from codegen.readfile import ReadError, read_regular

MAX_BYTES = 1 << 20  # 1 MiB: a calibration of 1,000 touches at 100 characters a row is a tenth of it
MAX_ROWS = 1_000  # data rows: a calibration takes 3 to a few dozen; more is a wrong file, and bounds the work
MAX_LINE = 1_000  # characters in one line
_NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")  # no '_', no nan or inf
_WHOLE = re.compile(r"[+-]?[0-9]+")


class CsvError(ValueError):
    """A file that is not a calibration CSV; the message names the file (and the line)."""


@dataclass(frozen=True)
class Row:
    line: int  # 1-based line of the file
    cells: tuple[str, ...]


def read_rows(path: Path, headers: tuple[tuple[str, ...], ...]) -> tuple[tuple[str, ...], list[Row]]:
    """The header (one of `headers`, compared without case and surrounding space) and the data rows that are
    not blank; every row has as many cells as the header. Refuses anything but a regular file (a FIFO would
    block for ever), files over MAX_BYTES or MAX_ROWS data rows, lines over MAX_LINE characters, text that is
    not UTF-8 (a byte-order mark is allowed) and NUL bytes."""
    text = _read_text(path)
    lines = text.splitlines()
    for number, line in enumerate(lines, start=1):
        if len(line) > MAX_LINE:
            raise CsvError(f"{path}:{number}: a line of {len(line):,} characters; at most {MAX_LINE:,}")
    expected = " or ".join(",".join(h) for h in headers)
    reader = csv.reader(lines, strict=True)
    try:
        first = next(reader, None)
        if first is None:
            raise CsvError(f"{path}: empty file; expected a header {expected}")
        header = tuple(cell.strip().lower() for cell in first)
        if header not in headers:
            raise CsvError(f"{path}:1: header must be {expected}, got {','.join(first)}")
        rows = []
        for cells in reader:
            line = reader.line_num
            if not cells or all(not cell.strip() for cell in cells):
                continue
            if len(rows) == MAX_ROWS:
                raise CsvError(f"{path}:{line}: more than {MAX_ROWS:,} rows; a calibration takes a few dozen at most")
            if len(cells) != len(header):
                raise CsvError(f"{path}:{line}: expected {len(header)} values {','.join(header)}, got {len(cells)}")
            rows.append(Row(line, tuple(cells)))
    except csv.Error as exc:
        raise CsvError(f"{path}:{reader.line_num}: not a CSV row ({exc})") from None
    return header, rows


def _read_text(path: Path) -> str:
    try:
        data = read_regular(path, MAX_BYTES, "a CSV file", f"a calibration file has at most {MAX_ROWS:,} rows")
    except ReadError as exc:
        raise CsvError(str(exc)) from None
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line, byte = data.count(b"\n", 0, exc.start) + 1, data[exc.start]
        raise CsvError(f"{path}:{line}: not UTF-8 text (byte 0x{byte:02x}); save the file as UTF-8") from None
    if "\0" in text:
        line = text.count("\n", 0, text.index("\0")) + 1
        raise CsvError(f"{path}:{line}: a NUL character: not a text file (UTF-16?); save the file as UTF-8")
    return text


def number(text: str) -> float:
    """A decimal number as a CSV holds one (digits, a point, an exponent): finite; ValueError otherwise. Python's
    float() also takes '2_000', 'nan', 'inf' and other scripts' digits: a calibration file must not."""
    stripped = text.strip()
    if not _NUMBER.fullmatch(stripped):
        raise ValueError(text)
    value = float(stripped)
    if not math.isfinite(value):
        raise ValueError(text)
    return value


def whole(text: str) -> int:
    """A whole number in decimal digits; ValueError otherwise (no '2_000', no '1e3')."""
    stripped = text.strip()
    if not _WHOLE.fullmatch(stripped):
        raise ValueError(text)
    return int(stripped)
