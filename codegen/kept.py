"""Results kept by the value of what they read: a digest of the inputs' values, field by field, and a bounded store."""

from __future__ import annotations

import hashlib
from collections import OrderedDict
from dataclasses import fields, is_dataclass

import numpy as np


class Kept:
    """Results kept by a digest of their inputs' values, the least recently used dropped first beyond `most`; an entry
    holds the objects its key names by identity, so their ids are not reused while it stands."""

    def __init__(self, most: int) -> None:
        self.most = most
        self.entries: OrderedDict = OrderedDict()

    def get(self, key: bytes):
        if key not in self.entries:
            return None
        self.entries.move_to_end(key)
        return self.entries[key][0]

    def put(self, key: bytes, made, held: list) -> None:
        self.entries[key] = (made, held)
        if len(self.entries) > self.most:
            self.entries.popitem(last=False)


def digest(*values, unread: dict | None = None) -> tuple[bytes, list]:
    """The SHA-256 of the values and the objects it names by identity; unread: dataclass type -> the fields left out.
    The bytes hashed are the repr of value_key's tree, a function of the values alone (pickle's bytes are not: it
    writes an object met twice as a reference to the first, so equal values shared or not would hash apart)."""
    held: list = []
    tree = tuple(value_key(v, unread or {}, held) for v in values)
    return hashlib.sha256(repr(tree).encode()).digest(), held


def value_key(obj, unread: dict, held: list) -> object:
    """A value equal for equal values, field by field, the unread fields left out; an object of another type by its
    id (appended to held, which keeps it alive)."""
    if isinstance(obj, float):
        return ("float", obj.hex())  # bit for bit: -0.0 and 0.0 differ, as printed
    if obj is None or isinstance(obj, (bool, int, str, bytes)):
        return (type(obj).__name__, obj)
    if isinstance(obj, np.ndarray):
        return ("array", obj.dtype.str, obj.shape, obj.tobytes())
    if isinstance(obj, np.generic):
        return ("scalar", obj.dtype.str, obj.tobytes())
    if is_dataclass(obj) and not isinstance(obj, type):
        skip = unread.get(type(obj), ())
        own = tuple((f.name, value_key(getattr(obj, f.name), unread, held)) for f in fields(obj) if f.name not in skip)
        return (type(obj).__qualname__, own)
    if isinstance(obj, (tuple, list)):
        return (type(obj).__name__, tuple(value_key(v, unread, held) for v in obj))
    if type(obj) is dict:
        return ("dict", tuple((value_key(k, unread, held), value_key(v, unread, held)) for k, v in obj.items()))
    if isinstance(obj, (set, frozenset)):
        return (type(obj).__name__, tuple(sorted((value_key(v, unread, held) for v in obj), key=repr)))
    held.append(obj)
    return ("same", id(obj))
