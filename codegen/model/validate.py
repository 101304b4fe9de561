"""Validation helpers for cell files: each error names the file and the key path (a CellError)."""

from __future__ import annotations

import math


class CellError(Exception):
    """A cell file that cannot be used; the message names the file and the line or key path."""


class Validator:
    """Validation helpers that know the file name and collect warnings; every error is a CellError naming
    the file and the key path."""

    def __init__(self, source: str) -> None:
        self.source = source
        self.warnings: list[str] = []

    def fail(self, key: str, message: str):
        raise CellError(f"{self.source}: {key}: {message}")

    def require(self, table: dict, key: str, path: str):
        if key not in table:
            self.fail(path, "missing")
        return table[key]

    def table(self, parent: dict, key: str, path: str) -> dict:
        value = self.require(parent, key, path)
        if not isinstance(value, dict):
            self.fail(path, f"expected a table, got {kind_of(value)}")
        return value

    def no_unknown(self, table: dict, allowed: set[str], path: str) -> None:
        unknown = sorted(set(table) - allowed)
        if unknown:
            self.fail(f"{path}.{unknown[0]}", f"unknown key; allowed: {', '.join(sorted(allowed))}")

    def number(self, table: dict, key: str, path: str) -> float:
        return self.finite(self.require(table, key, path), path)

    def finite(self, value, path: str) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            self.fail(path, f"expected a number, got {kind_of(value)}")
        value = float(value)
        if not math.isfinite(value):
            self.fail(path, f"expected a finite number, got {value}")
        return value

    def name(self, table: dict, key: str, path: str) -> str:
        value = self.require(table, key, path)
        if not isinstance(value, str) or not value.strip():
            self.fail(path, "expected a non-empty string")
        return value

    def numbers(self, value, count: int, path: str) -> tuple[float, ...]:
        if not isinstance(value, list):
            self.fail(path, f"expected {count} numbers, got {kind_of(value)}")
        if len(value) != count:
            self.fail(path, f"expected {count} numbers, got {len(value)}")
        return tuple(self.finite(v, f"{path}[{i}]") for i, v in enumerate(value))


def kind_of(value) -> str:
    """A value's kind as an error message names it."""
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, int | float):
        return f"the number {value}"
    if isinstance(value, str):
        return f"the string {value!r}"
    if isinstance(value, list):
        return f"a list of {len(value)}"
    if isinstance(value, dict):
        return "a table"
    return type(value).__name__
