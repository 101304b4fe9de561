"""Values shared by every dialect's interpreter: float32 numbers, records, signals, errors, formatting."""

from __future__ import annotations

import math

import numpy as np

from codegen.decimals import unsigned_zero

F32 = np.float32
MISSING = object()  # a lookup found nothing (None is a value)


class RunError(Exception):
    """A program that cannot run on: message starts with file:line:column when known."""


class StepLimitError(RunError):
    pass


class Halt(Exception):
    """The program stopped itself (halt / HALT / EXIT / Stop)."""


class Signal:
    """Non-local exits from statements: return, break, continue."""

    __slots__ = ("kind", "value")

    def __init__(self, kind: str, value=None) -> None:
        self.kind = kind
        self.value = value


BREAK = Signal("break")
CONTINUE = Signal("continue")


class Record(dict):
    """A structured value of a controller language (a frame, a pose, a target, a point).

    Records and arrays are never changed in place once made: assigning to a field or an element
    stores a changed copy along the path (see Compiler.lvalue). So variables can share values
    without copying, and still behave as the controllers' value semantics say."""

    __slots__ = ("type",)

    def __init__(self, type_name: str, fields=()) -> None:
        super().__init__(fields)
        self.type = type_name

    def copy(self) -> Record:
        return Record(self.type, {k: (v.copy() if isinstance(v, Record | list) else v) for k, v in self.items()})

    def shallow(self) -> Record:
        """A new record of the same class with the same field values (to change one of them)."""
        new = dict.__new__(type(self))
        dict.update(new, self)
        new.type = self.type
        return new


_ONE32 = F32(1.0)
_WEAK_PYTHON_FLOATS = type(_ONE32 * 0.1) is F32  # NumPy >= 2 (NEP 50)


def f32(value) -> np.float32:
    """value rounded to float32, exactly as F32(value). A Python float takes a path six times
    faster: under NEP 50 it is first rounded to float32, and x 1.0 in float32 is exact (sign of
    zero, inf and NaN included; overflow warns as F32 does)."""
    if _WEAK_PYTHON_FLOATS and type(value) is float:
        return _ONE32 * value
    return F32(value)


def constant(value):
    """An initialiser that gives every run the same value (safe: values are never changed in place);
    compiled routine entries store `.value` directly."""

    def initial(fr):
        return value

    initial.value = value
    return initial


# --- errors raised by generated code ------------------------------------------------------------


def op_error(where: str, exc: Exception) -> RunError:
    """An operator applied to values it does not take, as the controller would refuse it."""
    if isinstance(exc, ZeroDivisionError):
        return RunError(f"{where}: division by zero")
    if isinstance(exc, ValueError | OverflowError):  # int(nan), int(inf) as an index...
        return RunError(f"{where}: invalid value ({exc})")
    return RunError(f"{where}: type mismatch ({exc})")


def index_value(seq, index, offset: int, where: str):
    """seq[index] with the controller's index base; a record is indexed by its field order."""
    i = int(index) - offset
    if isinstance(seq, Record):
        seq = list(seq.values())
    if not 0 <= i < len(seq):
        raise RunError(
            f"{where}: index {i + offset} out of range 1..{len(seq)}"
            if offset
            else f"{where}: index {i} out of range 0..{len(seq) - 1}"
        )
    return seq[i]


def no_field(value, name: str, where: str):
    raise RunError(f"{where}: no field {name} in {getattr(value, 'type', type(value).__name__)}")


def no_field_to_set(value, name: str, where: str):
    raise RunError(f"{where}: no field {name} in {getattr(value, 'type', '?')}")


def bad_index(index: int, where: str):
    raise RunError(f"{where}: index {index} out of range")


# --- number formatting shared by message instructions -----------------------------------------


def format_fixed(value, decimals: int) -> str:
    """Fixed decimals with round-half-away-from-zero as controllers display, no '-0'."""
    v = float(value)
    if not math.isfinite(v):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
    scaled = abs(v) * 10**decimals
    rounded = math.floor(scaled + 0.5) / 10**decimals
    return unsigned_zero(f"{math.copysign(rounded, v):.{decimals}f}")


def format_general(value) -> str:
    """Shortest text that reads back to the same float32 (ints as ints)."""
    if isinstance(value, bool):
        return "True" if value else "False"
    if isinstance(value, int | np.integer):
        return str(int(value))
    v = value if type(value) is F32 else f32(value)
    if not math.isfinite(v):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
    text = str(v)  # numpy's shortest round-trip digits; positional for 1e-4 <= |v| < 1e16
    if "e" in text:
        return np.format_float_positional(v, trim="-", unique=True)
    return text[:-2] if text.endswith(".0") else text
