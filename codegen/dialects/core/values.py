"""Values shared by every dialect's interpreter: float32 numbers, records, signals, errors, formatting."""

from __future__ import annotations

import math
import re

import numpy as np

from codegen.decimals import unsigned_zero

F32 = np.float32
F32_MAX = float(np.finfo(F32).max)  # the largest number a float32 controller holds (3.4028235e38)
MISSING = object()  # a lookup found nothing (None is a value)


class RunError(Exception):
    """A program that cannot run on: message starts with file:line:column when known."""


class StepLimitError(RunError):
    pass


class Halt(Exception):
    """The program stopped itself (halt / HALT / EXIT / Stop)."""


class LimitReached(Exception):
    """The run reached a limit its caller set (Program.run's max_moves, max_seconds): it ends cleanly there,
    its trace kept (Trace.ended says why); not a RunError: nothing in the compiled code catches it."""


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


# What a message calls a value's kind: the controller's words, never a Python type's name.
PYTHON_KINDS = {
    "NoneType": "no value",
    "bool": "a boolean",
    "int": "an integer",
    "float": "a number",
    "float32": "a number",
    "float64": "a number",
    "numpy.float32": "a number",
    "numpy.float64": "a number",
    "numpy.int64": "an integer",
    "numpy.int32": "an integer",
    "numpy.bool": "a boolean",
    "numpy.bool_": "a boolean",
    "numpy.ndarray": "an array",
    "str": "a string",
    "list": "an array",
    "tuple": "an array",
    "dict": "a record",
    "function": "a routine",
    "Record": "a record",
}  # a dialect adds the kinds of its own values (a pose, a struct)


def describe(value) -> str:
    """A value's kind as a message names it ("a number", "a string", "an array", "a FRAME", "no value")."""
    record_type = getattr(value, "type", None) if isinstance(value, dict) else None
    if isinstance(record_type, str) and record_type:
        return f"a {record_type}"
    kind = PYTHON_KINDS.get(type(value).__name__)
    if kind is None and isinstance(value, np.generic):
        kind = "a number" if isinstance(value, np.floating) else "an integer"
    if kind is None:
        kind = getattr(value, "kind_name", None) or "a value of another kind"
    return kind


def show(value, limit: int = 40) -> str:
    """A value as a message shows it: a number's digits, a string in quotes, else its kind."""
    if isinstance(value, bool | int | float | np.number) and not isinstance(value, np.bool_):
        return format_general(value)
    if isinstance(value, str):
        return repr(value if len(value) <= limit else value[:limit] + "...")
    return describe(value)


_K = r"'?([\w.]+)'?"  # a Python type's name, quoted or not
# Python's own words for an operator refused: (pattern, what the message says: {op} and {a}, {b} the kinds)
_OPERANDS = (
    (re.compile(rf"unsupported operand type\(s\) for ([^:]+): {_K} and {_K}"), "{a} {op} {b}"),
    (re.compile(rf"'([^']+)' not supported between instances of {_K} and {_K}"), "{a} {op} {b}"),
    (re.compile(rf"bad operand type for unary ([^:]+): {_K}"), "{op} of {a}"),
    (re.compile(r'can only concatenate (\w+) \(not "([\w.]+)"\) to \w+'), "{a} + {b}"),
    (re.compile(rf"{_K} object is not subscriptable"), "an index of {a}"),
    (re.compile(rf"{_K} object is not iterable"), "the elements of {a}"),
    (re.compile(rf"object of type {_K} has no len\(\)"), "{a} has no elements"),
    (re.compile(rf"can't multiply sequence by non-int of type {_K}"), "an array * {a}"),
    (re.compile(rf"{_K} object cannot be interpreted as an integer"), "{a} as an integer"),
    (re.compile(rf"must be real number, not {_K}"), "{a} as a number"),
    (re.compile(rf"argument must be a string or a (?:real )?number, not {_K}"), "{a} as a number"),
)
_UFUNC = re.compile(r"ufunc '(\w+)'")
_UFUNC_OPS = {
    "add": "+",
    "subtract": "-",
    "multiply": "*",
    "divide": "/",
    "true_divide": "/",
    "remainder": "%",
    "less": "<",
    "less_equal": "<=",
    "greater": ">",
    "greater_equal": ">=",
    "equal": "==",
    "not_equal": "!=",
}
_DTYPE = re.compile(r"dtype\('([^']+)'\)")


def _dtype_word(dtype: str) -> str:
    kind = dtype.lstrip("<>|=")[:1]
    return {"U": "a string", "S": "a string", "f": "a number", "i": "an integer", "b": "a boolean"}.get(kind, "a value")


_INVALID = (
    (re.compile(r"cannot convert float NaN to integer"), "not a number where an integer is needed"),
    (re.compile(r"cannot convert float infinity to integer"), "an infinite number where an integer is needed"),
    (re.compile(r"math domain error"), "outside the function's domain"),
    (re.compile(r"math range error|result too large|too large to convert|out of range"), "a number out of range"),
    (re.compile(r"invalid literal for int\(\)"), "text that is not an integer"),
    (re.compile(r"could not convert string to float"), "text that is not a number"),
)


def _kind_word(python_name: str) -> str:
    return PYTHON_KINDS.get(python_name) or PYTHON_KINDS.get(python_name.rsplit(".", 1)[-1]) or "a value"


def op_error(where: str, exc: Exception) -> RunError:
    """An operator applied to values it does not take, as the controller would refuse it; the message names
    the operator and the kinds of its operands in the program's words, never Python's."""
    if isinstance(exc, ZeroDivisionError):
        return RunError(f"{where}: division by zero")
    if isinstance(exc, FloatingPointError):  # numpy under the run's errstate(over="raise"): a result past float32
        return RunError(f"{where}: arithmetic overflow (a result beyond the controller's numbers, {F32_MAX:.7g})")
    text = str(exc)
    if isinstance(exc, ValueError | OverflowError):  # int(nan), int(inf) as an index...
        said = next((words for pattern, words in _INVALID if pattern.search(text)), None)
        said = said or "a value the operation does not take"
        return RunError(f"{where}: invalid value ({said})")
    ufunc = _UFUNC.search(text)
    if ufunc is not None:  # numpy's words for a number and a string
        op = _UFUNC_OPS.get(ufunc.group(1), ufunc.group(1))
        kinds = [_dtype_word(d) for d in _DTYPE.findall(text)] + ["a value", "a value"]
        return RunError(f"{where}: type mismatch ({kinds[0]} {op} {kinds[1]})")
    for pattern, form in _OPERANDS:
        match = pattern.search(text)
        if match is not None:
            groups = list(match.groups())
            op = groups.pop(0) if "{op}" in form else ""
            kinds = [_kind_word(g) for g in groups] + ["", ""]
            return RunError(f"{where}: type mismatch ({form.format(op=op, a=kinds[0], b=kinds[1])})")
    return RunError(f"{where}: type mismatch (a value of a kind this operation does not take)")


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


def whole_index(value, where: str) -> int:
    """An index as a whole number; a RunError for one with a fraction (where the language takes no other)."""
    whole = int(value)
    if whole != value:
        raise RunError(f"{where}: index {format_general(value)} is not a whole number")
    return whole


def _record_name(value) -> str:
    record_type = getattr(value, "type", None) if isinstance(value, dict) else None
    return record_type if isinstance(record_type, str) and record_type else describe(value)


def no_field(value, name: str, where: str):
    raise RunError(f"{where}: no field {name} in {_record_name(value)}")


def no_field_to_set(value, name: str, where: str):
    raise RunError(f"{where}: no field {name} in {_record_name(value)}")


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
