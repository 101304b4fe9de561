"""Clearance proofs kept by the value of what they read: the paths, and the cell's clearance, arms, tool and solids."""

from __future__ import annotations

import hashlib
import pickle
from collections import OrderedDict
from dataclasses import fields, is_dataclass

import numpy as np

from codegen.world.cell import clearance_mm, solids, tool_shape
from codegen.world.proof import prove


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


# the proofs of the kinds that keep none of their own (generate's check of every path a kind plans): an entry is a
# few Least (about 0.5 kB each), so a full store stays well under 1 MB
PROVEN = Kept(128)


def proven(cell, paths: list) -> list:
    """prove(cell, paths) (codegen/world/proof.py), kept by the value of everything it reads: the paths, the cell's
    clearance, each path's arm, the tool (its TCP and its shape) and the cell's solids. A refusal is not kept (it
    raises every time, naming what the cell has now)."""
    key, held = proof_key(cell, paths)
    made = PROVEN.get(key)
    if made is None:
        made = prove(cell, paths)
        PROVEN.put(key, made, held)
    return list(made)


def proof_key(cell, paths: list) -> tuple[bytes, list]:
    """The digest of what prove reads for these paths, and the objects it names by identity."""
    robot = cell.robot
    arms = [robot.arms[path.target] for path in paths]
    return digest(paths, clearance_mm(cell), arms, robot.tool.tcp2flange, solids(cell), tool_shape(cell))


def digest(*values) -> tuple[bytes, list]:
    """The SHA-256 of the values (value_key, pickled: equal bytes only for equal values) and the objects it names by
    identity."""
    held: list = []
    data = pickle.dumps(tuple(value_key(v, held) for v in values), protocol=5)
    return hashlib.sha256(data).digest(), held


def value_key(obj, held: list) -> object:
    """A picklable value equal for equal values, field by field; an object of another type by its id (appended to
    held, which keeps it alive)."""
    if obj is None or isinstance(obj, (bool, int, float, str, bytes)):
        return (type(obj).__name__, obj)  # pickled bit for bit: -0.0 and 0.0 differ
    if isinstance(obj, np.ndarray):
        return ("array", obj.dtype.str, obj.shape, obj.tobytes())
    if isinstance(obj, np.generic):
        return ("scalar", obj.dtype.str, obj.tobytes())
    if is_dataclass(obj) and not isinstance(obj, type):
        return (type(obj).__qualname__, tuple((f.name, value_key(getattr(obj, f.name), held)) for f in fields(obj)))
    if isinstance(obj, (tuple, list)):
        return (type(obj).__name__, tuple(value_key(v, held) for v in obj))
    if type(obj) is dict:
        return ("dict", tuple((value_key(k, held), value_key(v, held)) for k, v in obj.items()))
    if isinstance(obj, (set, frozenset)):
        return (type(obj).__name__, tuple(sorted((value_key(v, held) for v in obj), key=repr)))
    held.append(obj)
    return ("same", id(obj))
