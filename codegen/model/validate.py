"""Validation helpers for cell files: each error names the file and the key path (a CellError)."""

from __future__ import annotations

import difflib
import math

from codegen.guard import TAUGHT_RANGE_MM
from codegen.model.lines import line_of, written
from codegen.poses import POSE_FORMATS

# One turn, the bound of every angle a cell file gives (orientations, pattern angles, offsets): the same
# rotation can always be written within it, and a float32 step at 360 deg is 3e-5 deg
ANGLE_BOUNDS = {"deg": 360.0, "rad": 2 * math.pi}
FLOAT32_TURN = "a float32 controller keeps an angle beyond one turn too coarsely (at 1e9 deg a float32 step is 64 deg)"
DIGITS_SHOWN = 12  # a number in a message is shown with at most this many digits
TYPO_CUTOFF = 0.8  # an unknown key this similar to an allowed one (difflib's ratio) is named as the one meant


def metres_hint(pose_format: str) -> str:
    """Why values too large for a metre-and-radian format are so: what that format takes and the way out."""
    if pose_format != "ur":
        return ""
    return (
        f' (pose_format = "ur" takes {POSE_FORMATS["ur"][3]}: values in mm and degrees are 1000 and 57 times too '
        'large; write metres and radians, or set pose_format = "xyzabc" for mm and degrees)'
    )


# The longest reach in the catalogue is 2,696 mm: a base-frame position written in metres reads as less than this
# many mm, where no arm's tool can be (inside its own base).
METRES_MAX_MM = 3.0


def read_as_metres(values) -> float | None:
    """The largest of a base-frame position's values where it reads as metres in a millimetre field, else None."""
    reach = max(abs(float(v)) for v in values)
    return reach if 0.0 < reach < METRES_MAX_MM else None


def metres_text(reach: float, subject: str) -> str:
    """The question a value that reads as metres gets (subject: "A mark is"): what it is in mm, and what it would be."""
    return f"given in metres? {subject} mm in the base frame: {reach:g} m is {reach * 1000.0:g} mm"


class CellError(Exception):
    """A cell file that cannot be used; the message names the file and the line or key path."""

    def __init__(self, message: str, source: str = "", key: str = "", detail: str = "") -> None:
        super().__init__(message)
        self.source, self.key, self.detail = source, key, detail

    def with_line(self, text: str) -> CellError:
        """The error with the line of its key in the cell file's text ("file: line N: key path: message"), or
        itself when it names no key or the key is not found in the text."""
        line = line_of(text, self.key) if self.key else None
        if line is None:
            return self
        key = self.key
        if not self.detail.startswith("missing") and not written(text, key):
            key += " (not in the file: its default)"  # the line is its table's, where the key would go
        return CellError(f"{self.source}: line {line}: {key}: {self.detail}", self.source, self.key, self.detail)


class Validator:
    """Validation helpers that know the file name and collect warnings; every error is a CellError naming
    the file and the key path."""

    def __init__(self, source: str) -> None:
        self.source = source
        self.warnings: list[str] = []

    def fail(self, key: str, message: str):
        raise CellError(f"{self.source}: {key}: {message}", self.source, key, message)

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
            near = difflib.get_close_matches(str(unknown[0]), sorted(allowed), n=1, cutoff=TYPO_CUTOFF)
            meant = f" (did you mean {near[0]!r}?)" if near else ""
            self.fail(f"{path}.{unknown[0]}", f"unknown key{meant}; allowed: {', '.join(sorted(allowed))}")

    def number(self, table: dict, key: str, path: str) -> float:
        return self.finite(self.require(table, key, path), path)

    def finite(self, value, path: str) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            self.fail(path, f"expected a number, got {kind_of(value)}")
        try:
            value = float(value)
        except OverflowError:  # an integer beyond a float64 (a controller's numbers are 32-bit)
            self.fail(path, f"expected a finite number, got {kind_of(value)}")
        if not math.isfinite(value):
            self.fail(path, f"expected a finite number, got {value}")
        return value

    def integer(self, table: dict, key: str, path: str, low: int, high: int, default: int | None = None) -> int:
        """An integer key in low..high (default: the value when the key is absent; None: the key is required).
        A number with a decimal point (16.0) is refused: the key counts something, and a float there is a
        typing error the programs would print as a REAL."""
        value = self.require(table, key, path) if default is None or key in table else default
        if isinstance(value, bool) or not isinstance(value, int):
            self.fail(path, f"expected a whole number (no decimal point) in {low}..{high}, got {kind_of(value)}")
        if not low <= value <= high:
            self.fail(path, f"expected a whole number in {low}..{high}, got {kind_of(value)}")
        return value

    def point(self, value, path: str) -> tuple[float, float, float]:
        """A taught point x, y, z (mm) within TAUGHT_RANGE_MM, as a taught pose's position."""
        numbers = self.numbers(value, 3, path)
        if max(abs(v) for v in numbers) > TAUGHT_RANGE_MM:
            self.fail(path, f"a taught point: within +-{TAUGHT_RANGE_MM:g} mm (float32 on the controller)")
        return numbers

    def angles(
        self, values: tuple[float, ...], path: str, unit: str = "deg", what: str = "angles", hint: str = ""
    ) -> tuple[float, ...]:
        """Angles within one turn (ANGLE_BOUNDS, deg or rad), as the taught poses' orientation: beyond it a
        float32 controller keeps the angle too coarsely (at 1e9 deg a float32 step is 64 deg). hint: what the
        format takes, where values beyond it are likely in another unit."""
        bound = ANGLE_BOUNDS[unit]
        if values and max(abs(v) for v in values) > bound:
            why = hint or f": {FLOAT32_TURN}"
            self.fail(path, f"{what} must be within +-{bound:g} {unit}{why}")
        return values

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
    if isinstance(value, int) and abs(value) >= 10**DIGITS_SHOWN:
        return f"an integer of {_digits(value)} digits"
    if isinstance(value, int | float):
        return f"the number {value}"
    if isinstance(value, str):
        return f"the string {value!r}"
    if isinstance(value, list):
        return f"a list of {len(value)}"
    if isinstance(value, dict):
        return "a table"
    return type(value).__name__


def _digits(value: int) -> str:
    """How many decimal digits an integer has (without converting a huge one to text: Python refuses
    integers of more than 4300 digits there)."""
    return str(len(str(abs(value)))) if value.bit_length() < 10_000 else f"about {int(value.bit_length() * 0.30103)}"
