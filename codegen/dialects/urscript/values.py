"""URScript values: poses p[x, y, z, rx, ry, rz], structs, and the argument checks every built-in shares."""

from __future__ import annotations

import math

import numpy as np

from codegen.dialects import posemath
from codegen.dialects.core.values import F32, PYTHON_KINDS, Record, RunError, describe, f32, format_general

MM_PER_M = 1000.0
# ints taken as 32-bit as the floats are (not confirmed in the manual's text, nor whether the controller wraps or
# stops past it): a value past them is refused where an operation or a built-in makes it
INT_BITS = 32
INT_RANGE = (-(2 ** (INT_BITS - 1)), 2 ** (INT_BITS - 1) - 1)


def int_overflow(value: int, what: str, where: str):
    raise RunError(f"{where}: integer overflow: {what} gives {value}, beyond the controller's 32-bit ints")


def int32(value, what: str, where: str):
    """value itself where it is not an int or is one of the controller's; else the overflow error naming what made
    it."""
    if type(value) is int and not INT_RANGE[0] <= value <= INT_RANGE[1]:
        int_overflow(value, what, where)
    return value


class URPose(Record):
    """p[x, y, z, rx, ry, rz] (m, rad), indexable 0..5; its elements also by name (pose.x ... pose.rz)."""

    KEYS = ("x", "y", "z", "rx", "ry", "rz")

    def __init__(self, values) -> None:
        super().__init__("pose", zip(self.KEYS, (f32(v) for v in values), strict=True))

    def copy(self) -> URPose:
        return URPose(self.values())


class Struct(Record):
    """struct(name=value, ...): named values, each read and changed by its name (s.name)."""

    def __init__(self, fields) -> None:
        super().__init__("struct", fields)


PYTHON_KINDS.update({"URPose": "a pose", "Struct": "a struct", "URThread": "a thread"})  # in messages


def num(value, where: str, what: str):
    """A number argument (int or float32), else a RunError naming what it is."""
    kind = type(value)
    if kind is F32 or kind is float or kind is int:  # the common cases first
        return value
    if isinstance(value, bool) or not isinstance(value, int | float | np.number):
        raise RunError(f"{where}: {what} must be a number, got {describe(value)}")
    return value


def pose(value, where: str, what: str = "argument") -> URPose:
    if not isinstance(value, URPose):
        raise RunError(f"{where}: {what}: expected a pose p[...], got {describe(value)}")
    return value


def joints(value, where: str, count: int = 6, what: str = "list") -> np.ndarray:
    """A list of `count` finite numbers, as float64."""
    if not isinstance(value, list) or len(value) != count:
        raise RunError(f"{where}: {what}: expected a list of {count} numbers, got {describe(value)}")
    out = np.array([float(num(v, where, f"{what} element")) for v in value])
    posemath.check_finite(tuple(out), where, what)
    return out


def vector(value, where: str, what: str = "vector") -> np.ndarray:
    """Three numbers: a list [a, b, c] (or a pose's position where the manual allows a pose)."""
    if isinstance(value, URPose):
        value = list(value.values())[:3]
    return joints(value, where, 3, what)


def matrix(value, where: str, what: str = "pose") -> np.ndarray:
    """A pose argument as a 4x4 matrix (mm), its numbers checked finite."""
    p = pose(value, where, what)
    posemath.check_finite(p.values(), where, what)
    return posemath.matrix_from_ur(p.values())


def arguments(name: str, params: tuple[str, ...], defaults: dict, args, kwargs, where: str) -> dict:
    """A built-in's arguments by parameter name: positional ones in order, then named ones, then the
    defaults the manual gives; a RunError for one too many, an unknown name or one missing."""
    if not kwargs and len(args) == len(params):  # the common call: every argument in order
        return dict(zip(params, args, strict=True))
    given = len(args) + len(kwargs)
    if len(args) > len(params):
        raise RunError(f"{where}: {_takes(name, params, defaults)}: too many arguments ({given} given)")
    bound = dict(zip(params, args, strict=False))
    for key, value in kwargs.items():
        if key not in params:
            raise RunError(f"{where}: {name} has no parameter {key}")
        if key in bound:
            raise RunError(f"{where}: {name}: argument {key} given twice")
        bound[key] = value
    for key in params:
        if key not in bound:
            if key not in defaults:
                raise RunError(f"{where}: {_takes(name, params, defaults)}: too few arguments ({given} given)")
            bound[key] = defaults[key]
    return bound


def _takes(name: str, params: tuple[str, ...], defaults: dict) -> str:
    """How a message states what a built-in takes: f(a, b) takes one argument, 2 arguments, 1 to 3 arguments."""
    required = sum(1 for p in params if p not in defaults)
    count = len(params)
    if required == count:
        words = "no arguments" if count == 0 else "one argument" if count == 1 else f"{count} arguments"
    else:
        words = f"{required} to {count} arguments"
    return f"{name}({', '.join(params)}) takes {words}"


def to_text(value) -> str:
    """A value as textmsg and to_str write it."""
    if isinstance(value, str):
        return value
    if isinstance(value, URPose):
        return "p[" + ", ".join(format_general(v) for v in value.values()) + "]"
    if isinstance(value, Struct):
        return "struct(" + ", ".join(f"{k}={to_text(v)}" for k, v in value.items()) + ")"
    if isinstance(value, list):
        return "[" + ", ".join(to_text(v) for v in value) + "]"
    if value is None:
        return "None"
    return format_general(value)


def unary(fn, what: str = "argument"):
    """A one-number math built-in computed in float64 and stored as float32."""

    def call(fr, args, kwargs, where):
        if len(args) + len(kwargs) != 1:
            raise RunError(f"{where}: expected 1 argument")
        value = args[0] if args else next(iter(kwargs.values()))
        try:
            return f32(fn(float(num(value, where, what))))
        except (ValueError, OverflowError):
            raise RunError(f"{where}: {value} is outside the function's domain") from None

    return call


def finite(value: float, where: str, what: str) -> float:
    if not math.isfinite(value):
        raise RunError(f"{where}: {what} must be a finite number, got {format_general(value)}")
    return value
