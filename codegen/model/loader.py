"""The generic cell-file loader: a table read by its declared keys, then a frozen dataclass built by keyword."""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from dataclasses import fields
from typing import Any

from codegen.guard import TAUGHT_RANGE_MM
from codegen.model.schema import Key, Table
from codegen.model.validate import ANGLE_BOUNDS, Validator, kind_of

# A key whose value needs more than its declaration (the cell's targets, a controller's facts): (raw value or
# None when the key is absent, its key path) -> its value
Reader = Callable[[Any, str], Any]
# the Python values each declared type accepts (either: the alternative whose shape the value has)
_SHAPES: dict[str, tuple[type, ...]] = {
    "string": (str,),
    "boolean": (bool,),
    "integer": (int,),
    "number": (int, float),
    "numbers": (list,),
    "pose": (list,),
    "list": (list,),
    "tables": (list,),
    "table": (dict,),
    "map": (dict,),
}


class Loader:
    """Reads tables of a cell file by their declarations (codegen.model.schema): the types, ranges, allowed values,
    defaults, required and unknown keys; every error a CellError naming the key path (through the Validator)."""

    def __init__(self, ctx: Validator, pose_format: str = "xyzabc", targets: tuple[str, ...] = ()) -> None:
        self.ctx = ctx
        self.pose_format = pose_format
        self.targets = tuple(targets)  # the cell's targets: the entries of a per_target map

    def table(self, table: Table, raw, path: str, readers: Mapping[str, Reader] | None = None) -> dict[str, Any]:
        """A table's values by key name: each key read by its declaration (or by its reader), an absent one
        its default (None: no default); an unknown key refused."""
        readers = readers or {}
        if not isinstance(raw, dict):
            self.ctx.fail(path, f"expected a table, got {kind_of(raw)}")
        self.ctx.no_unknown(raw, table.allowed, path)
        out: dict[str, Any] = {}
        for name, key in table.keys.items():
            where = f"{path}.{name}"
            if name in readers:
                out[name] = readers[name](raw.get(name), where)
            elif name in raw:
                out[name] = self.value(key, raw[name], where, name)
            elif key.required:
                self.ctx.fail(where, f"missing: {key.doc}{_from(key.values, ': ')}")
            else:
                out[name] = {} if key.per_target else key.default
        return out

    def value(self, key: Key, raw, path: str, name: str | None = None):
        """One value checked against its key: tuples for lists and numbers, dicts for tables and maps (name: its key's
        or its map entry's, a taught pose's name as the cell wrote it)."""
        if key.type == "either":
            return self._either(key, raw, path, name)
        if key.type == "pose":
            return self.ctx.pose(path.rsplit(".", 1)[-1] if name is None else name, raw, path, self.pose_format)
        if key.expected and not _fits(key, raw):
            self.ctx.fail(path, f"expected {key.expected}, got {kind_of(raw)}")
        if not _has_shape(raw, key.type):
            wanted = "must be true or false" if key.type == "boolean" else f"expected {_expected(key)}"
            if key.choices:  # the values allowed say more than their type (a whole number's decimal point as much)
                allowed = f"one of {_listed(key.choices)} ({key.doc})"
                wanted = f"{wanted}, {allowed}" if key.type == "integer" else f"expected {allowed}"
            self.ctx.fail(path, f"{wanted}, got {kind_of(raw)}")
        return getattr(self, f"_{key.type}")(key, raw, path)

    def _string(self, key: Key, raw: str, path: str) -> str:
        if key.non_empty and not raw.strip():
            self.ctx.fail(path, "expected a non-empty string")
        self._choice(key, raw, path)
        if key.pattern and not re.fullmatch(key.pattern, raw):
            self.ctx.fail(path, f"expected {key.doc} (the whole of it matching {key.pattern}), got {raw!r}")
        return raw

    def _boolean(self, key: Key, raw: bool, path: str) -> bool:
        return raw

    def _integer(self, key: Key, raw: int, path: str) -> int:
        self._choice(key, raw, path)
        if not key.contains(raw):
            self.ctx.fail(path, f"expected a whole number {_whole_range(key)} ({key.doc}), got {kind_of(raw)}")
        return raw

    def _number(self, key: Key, raw, path: str) -> float:
        number = self.ctx.finite(raw, path)
        self._choice(key, number, path)
        if not key.contains(number):
            self.ctx.fail(path, f"must be {_range(key)} ({key.doc}), got {number:g}")
        return number

    def _numbers(self, key: Key, raw: list, path: str) -> tuple[float, ...]:
        if key.unit == "mm" and key.count == 3 and key.bounds == (-TAUGHT_RANGE_MM, TAUGHT_RANGE_MM):
            return self.ctx.point(raw, path)  # a taught point: the controller's float32 reason in the message
        numbers = self.ctx.numbers(raw, key.count, path)
        if key.unit in ANGLE_BOUNDS and key.bounds == (-ANGLE_BOUNDS[key.unit], ANGLE_BOUNDS[key.unit]):
            return self.ctx.angles(numbers, path, key.unit)
        # the taught range's reason (a calibration mark's x and y are taught coordinates too)
        why = " (float32 on the controller)" if key.bounds == (-TAUGHT_RANGE_MM, TAUGHT_RANGE_MM) else ""
        for i, number in enumerate(numbers):
            if not key.contains(number):
                self.ctx.fail(f"{path}[{i}]", f"must be {_range(key)} ({key.doc}), got {number:g}{why}")
        return numbers

    def _list(self, key: Key, raw: list, path: str) -> tuple:
        if key.count is not None and len(raw) != key.count:
            self.ctx.fail(path, f"expected {key.count} values ({key.doc}), got {len(raw)}")
        if key.non_empty and not raw:
            self.ctx.fail(path, f"expected at least one value ({key.doc}{_from(key.values, ': ')})")
        out = tuple(self.value(key.values, v, f"{path}[{i}]") for i, v in enumerate(raw))
        if key.unique:
            for i, v in enumerate(out):
                if v in out[:i]:
                    self.ctx.fail(f"{path}[{i}]", f"{v!r} listed twice")
        return out

    def _table(self, key: Key, raw: dict, path: str) -> dict[str, Any]:
        return self.table(key.table, raw, path)

    def _tables(self, key: Key, raw: list, path: str) -> tuple[dict[str, Any], ...]:
        if key.non_empty and not raw:
            self.ctx.fail(path, f"expected at least one table ({key.doc})")
        return tuple(self.table(key.table, t, f"{path}[{i}]") for i, t in enumerate(raw))

    def _map(self, key: Key, raw: dict, path: str) -> dict[str, Any]:
        if key.per_target:
            return self._per_target(key, raw, path)
        if key.names is not None:
            self.ctx.no_unknown(raw, set(key.names), path)
        if key.non_empty and not raw:
            self.ctx.fail(path, f"expected at least one entry ({key.doc})")
        out = {}
        for name, value in raw.items():
            sub = key.per_name.get(name, key.values)
            out[name] = value if sub is None else self.value(sub, value, f"{path}.{name}", name)
        return out

    def _per_target(self, key: Key, raw: dict, path: str) -> dict[str, Any]:
        """An entry for each of the cell's targets with its own key (per_name), checked by it; a target without one
        refused (key.lacking) or passed over; no other entry."""
        out = {}
        for target in self.targets:
            sub = key.per_name.get(target)
            if sub is None:
                if key.lacking:
                    self.ctx.fail(path, key.lacking.format(target=target))
                continue
            if target not in raw:
                self.ctx.fail(f"{path}.{target}", f"missing: {sub.doc} (every target of the cell names it)")
            out[target] = self.value(sub, raw[target], f"{path}.{target}", target)
        self.ctx.no_unknown(raw, set(out), path)
        return out

    def _either(self, key: Key, raw, path: str, name: str | None):
        for alternative in key.alternatives:
            if _has_shape(raw, alternative.type):
                return self.value(alternative, raw, path, name)
        self.ctx.fail(path, f"expected {' or '.join(_expected(k) for k in key.alternatives)}, got {kind_of(raw)}")

    def _choice(self, key: Key, value, path: str) -> None:
        if key.choices and value not in key.choices:
            self.ctx.fail(path, f"expected one of {_listed(key.choices)} ({key.doc}), got {value!r}")


def build(cls: type, values: Mapping[str, Any], table: Table | None = None, **more):
    """A frozen dataclass by keyword from a table's values: a nested table its declaration flattens (Key.flatten)
    gives its keys with the prefix (slip_sheet -> slip_: every -> slip_every); a value None leaves the field's
    default."""
    kwargs: dict[str, Any] = {}
    for name, value in values.items():
        prefix = None if table is None else table[name].flatten
        if prefix is not None:
            kwargs.update({prefix + k: v for k, v in (value or {}).items() if v is not None})
        elif value is not None:
            kwargs[name] = value
    kwargs.update(more)
    names = {f.name for f in fields(cls)}
    unknown = sorted(set(kwargs) - names)
    if unknown:  # a key declared without its field: the declaration and the dataclass disagree
        raise TypeError(f"{cls.__name__} has no field for {', '.join(unknown)}")
    return cls(**kwargs)


def _fits(key: Key, raw) -> bool:
    """Whether a value has the key's type and lies in its range, matches its pattern and choices."""
    if not _has_shape(raw, key.type) or (key.choices and raw not in key.choices):
        return False
    if key.type in ("integer", "number"):
        return key.contains(raw)
    return key.type != "string" or not key.pattern or re.fullmatch(key.pattern, raw) is not None


def _has_shape(raw, type_name: str) -> bool:
    if isinstance(raw, bool):
        return type_name == "boolean"
    return isinstance(raw, _SHAPES[type_name])


def _expected(key: Key) -> str:
    """What a value of the key is, as a message says it."""
    count = f"{key.count} " if isinstance(key.count, int) else ""
    return {
        "string": "a string",
        "boolean": "true or false",
        "integer": f"a whole number (no decimal point) {_whole_range(key)}".rstrip(),
        "number": "a number",
        "numbers": f"a list of {count}numbers",
        "pose": "a taught pose (a list of numbers)",
        "list": f"a list{_from(key.values, ' from ')}",
        "tables": "a list of tables",
        "table": "a table",
        "map": "a table",
    }[key.type]


def _from(values: Key | None, lead: str) -> str:
    """The values a list's entries are chosen from, as a message lists them after `lead` ('' when they are free)."""
    return "" if values is None or not values.choices else lead + _listed(values.choices)


def _listed(choices: tuple) -> str:
    return ", ".join(repr(c) if isinstance(c, str) else str(c) for c in choices)


def _whole_range(key: Key) -> str:
    if key.low is not None and key.high is not None and not (key.open_low or key.open_high):
        return f"in {key.low}..{key.high}"
    return key.range_text()


def _range(key: Key) -> str:
    text = key.range_text()
    text = f"in {text}" if text[:1] in "[(" else text
    return f"{text} {key.unit}".rstrip()
