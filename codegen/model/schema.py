"""The cell file's definition as data: each table and key (type, unit, range, default, users), and its JSON Schema."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

JSON_SCHEMA_DRAFT = "https://json-schema.org/draft/2020-12/schema"
NON_BLANK = r"\S"  # a string with something but spaces in it (the loader's non-empty names)


@dataclass(frozen=True)
class Key:
    """One key of a cell file: its type and what the loader accepts.

    type: "string", "integer", "number", "boolean", "numbers" (a list of `count` numbers, each in the range),
    "pose" (a taught pose in the cell's pose format), "list" (of `values`), "table" (the keys of `table`),
    "tables" (a list of `table`), "map" (names -> `values`; `names`: the names allowed, None: any), "either" (one of
    `alternatives`). low/high: the range (open_low/open_high: the bound itself refused); choices: the values
    allowed; kinds: the program kinds that use it (empty: every kind); controllers: which controllers."""

    type: str
    doc: str
    unit: str = ""
    low: float | None = None
    high: float | None = None
    open_low: bool = False
    open_high: bool = False
    choices: tuple = ()
    default: Any = None
    required: bool = False
    count: int | tuple[int, int] | None = None
    table: Table | None = None
    values: Key | None = None
    names: tuple[str, ...] | None = None
    per_name: dict = field(default_factory=dict)  # map: name -> its own Key (e.g. a signal per controller)
    alternatives: tuple[Key, ...] = ()
    kinds: tuple[str, ...] = ()
    controllers: str = ""
    pattern: str = ""  # a string: the whole of it matches this regular expression
    unique: bool = False  # a list: no value twice
    non_empty: bool = False  # a string with more than spaces, a list or table with at least one entry
    # a map with one entry for each of the cell's targets (the loader's) that has its key in per_name, each required;
    # lacking: the refusal of a cell target without one ({target}; "": it has no entry), absent: no entries
    per_target: bool = False
    lacking: str = ""
    expected: str = ""  # what a value that does not fit is refused as: "expected <this>, got <the value>"
    # a table whose keys are fields of the dataclass built from its parent (codegen.model.loader.build), named with
    # this prefix (slip_sheet -> "slip_": its every -> slip_every); None: the table is one field
    flatten: str | None = None

    @property
    def bounds(self) -> tuple[float | None, float | None]:
        return self.low, self.high

    def contains(self, value: float) -> bool:
        """Whether a number lies in the key's range."""
        if self.low is not None and (value <= self.low if self.open_low else value < self.low):
            return False
        return not (self.high is not None and (value >= self.high if self.open_high else value > self.high))

    def range_text(self) -> str:
        """The range as the reference writes it: [0, 90], (0, 180), >= 1, or ''."""
        if self.low is None and self.high is None:
            return ""
        if self.high is None:
            return f"{'>' if self.open_low else '>='} {_num(self.low)}"
        if self.low is None:
            return f"{'<' if self.open_high else '<='} {_num(self.high)}"
        return f"{'(' if self.open_low else '['}{_num(self.low)}, {_num(self.high)}{')' if self.open_high else ']'}"


@dataclass(frozen=True)
class Table:
    """A table of a cell file: its keys by name (a closed table: no other key is allowed)."""

    doc: str
    keys: dict[str, Key]
    kinds: tuple[str, ...] = ()

    def __getitem__(self, name: str) -> Key:
        return self.keys[name]

    @property
    def allowed(self) -> frozenset[str]:
        """The keys the loader accepts in this table (its no_unknown set)."""
        return frozenset(self.keys)

    @property
    def required(self) -> tuple[str, ...]:
        return tuple(name for name, key in self.keys.items() if key.required)

    def default(self, name: str):
        return self.keys[name].default

    def merged(self, more: dict[str, Key]) -> Table:
        return Table(self.doc, {**self.keys, **more}, self.kinds)


@dataclass(frozen=True)
class KindKeys:
    """A program kind's part of the cell file: its top-level tables, its [cell.<name>] tables, its [[station]]
    keys (a station kind's)."""

    tables: dict[str, Key] = field(default_factory=dict)
    cell_tables: dict[str, Key] = field(default_factory=dict)
    station_keys: dict[str, Key] = field(default_factory=dict)
    reads: tuple[str, ...] = ()  # the shared [cell.<name>] tables its programs use (e.g. "io")


def _num(value) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


# --- JSON Schema ---------------------------------------------------------------------------------


def json_of(key: Key) -> dict:
    """The JSON Schema of one key's value."""
    out: dict[str, Any] = {"description": key.doc + (f" ({key.unit})" if key.unit else "")}
    if key.default is not None:
        out["default"] = list(key.default) if isinstance(key.default, tuple) else key.default
    if key.type in ("string", "integer", "number", "boolean"):
        out.update(_scalar(key))
    elif key.type in ("numbers", "pose"):
        out["type"] = "array"
        out["items"] = {"type": "number", **_range(key)}
        low, high = key.count if isinstance(key.count, tuple) else (key.count, key.count)
        out["minItems"], out["maxItems"] = low, high
    elif key.type == "list":
        out["type"] = "array"
        out["items"] = json_of(key.values)
        if key.count is not None:
            out["minItems"] = out["maxItems"] = key.count
        elif key.non_empty:
            out["minItems"] = 1
        if key.unique:
            out["uniqueItems"] = True
    elif key.type == "table":
        out.update(json_of_table(key.table))
    elif key.type == "tables":
        out["type"] = "array"
        out["items"] = json_of_table(key.table)
        if key.non_empty:
            out["minItems"] = 1
    elif key.type == "map":
        out["type"] = "object"
        if key.names is not None:
            out["propertyNames"] = {"enum": list(key.names)}
        if key.per_name:
            out["properties"] = {name: json_of(k) for name, k in key.per_name.items()}
        if key.values is not None:
            out["additionalProperties"] = json_of(key.values)
        if key.non_empty:
            out["minProperties"] = 1
    elif key.type == "either":
        out["anyOf"] = [json_of(k) for k in key.alternatives]
    else:
        raise ValueError(f"unknown key type {key.type!r}")
    return out


def _scalar(key: Key) -> dict:
    out: dict[str, Any] = {"type": key.type}
    if key.choices:
        out["enum"] = list(key.choices)
    out.update(_range(key))
    if key.type == "string" and key.non_empty:
        out["pattern"] = NON_BLANK
    if key.pattern:
        out["pattern"] = f"^{key.pattern}$"
    return out


def _range(key: Key) -> dict:
    out = {}
    if key.low is not None:
        out["exclusiveMinimum" if key.open_low else "minimum"] = key.low
    if key.high is not None:
        out["exclusiveMaximum" if key.open_high else "maximum"] = key.high
    return out


def json_of_table(table: Table) -> dict:
    out: dict[str, Any] = {
        "type": "object",
        "description": table.doc,
        "properties": {name: json_of(key) for name, key in table.keys.items()},
        "additionalProperties": False,
    }
    if table.required:
        out["required"] = list(table.required)
    return out


# --- the reference page ----------------------------------------------------------------------------

REFERENCE_NOTE = "Generated by `codegen schema --markdown`"  # the page's first lines: codegen wrote it


def markdown(root: Table, title: str) -> str:
    """The cell-file reference: a section per table, a row per key (type, unit, range, default, users)."""
    lines = [
        f"# {title}",
        "",
        f"{REFERENCE_NOTE} from the loader's own definition; do not edit.",
        "",
    ]
    _tables(root, "", lines)
    return "\n".join(lines).rstrip() + "\n"


def _tables(table: Table, path: str, lines: list[str]) -> None:
    if path:
        lines += [f"## `[{path}]`", "", table.doc, ""]
        # the description beside the key: a page of 1,280 px shows it without scrolling the table sideways
        lines += ["| key | description | type | unit | range / values | default | required | used by |"]
        lines += ["|---|---|---|---|---|---|---|---|"]
        for name, key in table.keys.items():
            lines.append(
                f"| `{name}` | {key.doc.replace('|', '/')} | {_type(key)} | {key.unit} | {_values(key)} | "
                f"{_default(key)} | {'yes' if key.required else ''} | {_users(key, table)} |"
            )
        lines.append("")
    for name, key in table.keys.items():
        sub = key.table if key.type in ("table", "tables") else None
        if sub is None:
            sub = next((k.table for k in key.alternatives if k.type == "table"), None)
            name = f"{name}.<name>" if sub is not None else name
        if sub is not None:
            _tables(sub, f"{path}.{name}" if path else name, lines)


def _type(key: Key) -> str:
    if key.type in ("numbers", "pose"):
        low, high = key.count if isinstance(key.count, tuple) else (key.count, key.count)
        return f"{key.type} ({low}{'' if low == high else f'-{high}'})"
    if key.type == "either":
        return " or ".join(_type(k) for k in key.alternatives)
    if key.type == "list" and key.values is not None:
        return f"list of {_type(key.values)}"
    return key.type


def _values(key: Key) -> str:
    parts = []
    if key.choices:
        parts.append(", ".join(f"`{c}`" for c in key.choices))
    if key.range_text():
        parts.append(key.range_text())
    if key.names:
        parts.append("keys: " + ", ".join(f"`{n}`" for n in key.names))
    for name, sub in key.per_name.items():
        inner = _values(sub) or ("a name" if sub.pattern else "")
        if inner:
            parts.append(f"{name}: {inner}")
    if key.values is not None and key.type in ("list", "map"):
        inner = _values(key.values)
        if inner:
            parts.append(inner)
    for alternative in key.alternatives:
        inner = _values(alternative)
        if inner:
            parts.append(inner)
    return "; ".join(parts)


def _default(key: Key) -> str:
    if key.default is None:
        return ""
    value = key.default
    if isinstance(value, bool):
        return f"`{str(value).lower()}`"
    if isinstance(value, tuple):
        return "`[" + ", ".join(_num(v) for v in value) + "]`"
    return f"`{value!r}`" if isinstance(value, str) else f"`{_num(value)}`"


def _users(key: Key, table: Table) -> str:
    kinds = key.kinds or table.kinds
    out = ", ".join(kinds) if kinds else "all"
    return f"{out}; {key.controllers}" if key.controllers else out
