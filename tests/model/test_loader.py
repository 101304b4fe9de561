"""The generic loader: a table read by its declaration (bound, default, unknown key, type, missing key), the
dataclass built by keyword, and the line each message names."""

from __future__ import annotations

import tomllib
from dataclasses import dataclass

import jsonschema
import pytest
from support.cells import EXAMPLES

from codegen.model.cell import CellError, CellValidator, load_cell
from codegen.model.lines import key_lines, line_of
from codegen.model.loader import Loader, build
from codegen.model.schema import Key, Table, json_of_table

DEMO = Table(
    "A table to read.",
    {
        "name": Key("string", "the thing's name", required=True, non_empty=True),
        "speed": Key("number", "how fast", unit="mm/s", low=0.0, open_low=True, high=10.0, default=2.5),
        "count": Key("integer", "how many", low=1, high=5, default=1),
        "side": Key("string", "which side", choices=("left", "right"), default="left"),
        "flag": Key("boolean", "on or off", default=False),
        "offset": Key("numbers", "x, y", unit="mm", count=2, low=-100.0, high=100.0, default=(0.0, 0.0)),
        "turn": Key("numbers", "a, b, c", unit="deg", count=3, low=-360.0, high=360.0),
        "wait": Key(
            "either",
            "a duration or [least, most]",
            default=0.0,
            alternatives=(
                Key("number", "a duration", unit="s", low=0.0, high=2.0),
                Key("numbers", "[least, most]", unit="s", count=2, low=0.0, high=2.0),
            ),
        ),
        "per": Key("map", "a number per side", names=("left", "right"), values=Key("integer", "n", low=0, high=9)),
        "inner": Key(
            "table",
            "a table in it",
            table=Table("inner", {"depth": Key("number", "d", required=True)}),
            flatten="inner_",
        ),
    },
)


@dataclass(frozen=True)
class Thing:
    name: str
    speed: float = 2.5
    count: int = 1
    side: str = "left"
    flag: bool = False
    offset: tuple = (0.0, 0.0)
    turn: tuple | None = None
    wait: object = 0.0
    per: dict | None = None
    inner_depth: float = 0.0


def _read(raw: dict) -> dict:
    return Loader(CellValidator("cell.toml")).table(DEMO, raw, "demo")


def _error(raw: dict) -> str:
    with pytest.raises(CellError) as info:
        _read(raw)
    return str(info.value)


def test_absent_keys_take_their_declared_defaults_and_the_dataclass_is_built_by_keyword():
    thing = build(Thing, _read({"name": "a", "inner": {"depth": 4}}), DEMO)
    assert thing == Thing("a", 2.5, 1, "left", False, (0.0, 0.0), None, 0.0, None, 4.0)


def test_given_values_are_read_as_written():
    raw = {"name": "a", "speed": 10, "count": 5, "side": "right", "flag": True, "offset": [1, -2], "wait": [0.5, 1]}
    values = _read({**raw, "turn": [0, 90, -360], "per": {"left": 3}})
    assert (values["speed"], values["count"], values["offset"], values["wait"]) == (10.0, 5, (1.0, -2.0), (0.5, 1.0))
    assert values["turn"] == (0.0, 90.0, -360.0) and values["per"] == {"left": 3} and values["inner"] is None


@pytest.mark.parametrize(
    ("raw", "says"),
    [
        # a bound (open: the bound itself refused)
        ({"speed": 0.0}, "demo.speed: must be in (0, 10] mm/s (how fast), got 0"),
        ({"speed": 10.5}, "demo.speed: must be in (0, 10] mm/s (how fast), got 10.5"),
        ({"count": 6}, "demo.count: expected a whole number in 1..5 (how many), got the number 6"),
        ({"offset": [0, 101]}, "demo.offset[1]: must be in [-100, 100] mm (x, y), got 101"),
        ({"turn": [0, 0, 361]}, "demo.turn: angles must be within +-360 deg"),
        ({"wait": 3}, "demo.wait: must be in [0, 2] s (a duration), got 3"),
        ({"per": {"right": 10}}, "demo.per.right: expected a whole number in 0..9 (n), got the number 10"),
        # an unknown key, at the top and in a map with its names
        ({"colour": "red"}, "demo.colour: unknown key; allowed: count, flag, inner, name, offset, per, side, speed,"),
        ({"per": {"middle": 1}}, "demo.per.middle: unknown key; allowed: left, right"),
        # a wrong type
        ({"count": 2.0}, "demo.count: expected a whole number (no decimal point) in 1..5, got the number 2.0"),
        ({"speed": "fast"}, "demo.speed: expected a number, got the string 'fast'"),
        ({"flag": "yes"}, "demo.flag: must be true or false, got the string 'yes'"),
        ({"offset": [1]}, "demo.offset: expected 2 numbers, got 1"),
        ({"wait": "long"}, "demo.wait: expected a number or a list of 2 numbers, got the string 'long'"),
        ({"inner": 1}, "demo.inner: expected a table, got the number 1"),
        # an allowed value
        ({"side": "up"}, "demo.side: expected one of 'left', 'right' (which side), got 'up'"),
        # a missing key, at the top and in a table in it
        ({"name": None}, "demo.name: missing: the thing's name"),
        ({"inner": {}}, "demo.inner.depth: missing: d"),
        ({"name": "  "}, "demo.name: expected a non-empty string"),
    ],
)
def test_each_error_names_the_file_the_key_path_and_what_is_allowed(raw, says):
    given = {"name": "a", **raw}
    assert _error({k: v for k, v in given.items() if v is not None}).startswith(f"cell.toml: {says}")


def test_the_json_schema_of_a_declaration_refuses_what_the_loader_refuses():
    """The loader and the JSON Schema read one declaration: for each value the two agree (but 2.0 for an integer,
    which JSON Schema takes as a whole number and TOML writes as a float)."""
    validator = jsonschema.Draft202012Validator(json_of_table(DEMO))
    cases = [
        {"speed": 0.0},
        {"speed": 10.0},
        {"count": 6},
        {"offset": [0, 101]},
        {"offset": [0, 100]},
        {"side": "up"},
        {"per": {"middle": 1}},
        {"per": {"left": 9}},
        {"wait": [0, 2]},
        {"wait": 3},
        {"colour": "red"},
        {"inner": {}},
        {"inner": {"depth": 1}},
    ]
    for case in cases:
        raw = {"name": "a", **case}
        try:
            _read(raw)
            loaded = True
        except CellError:
            loaded = False
        assert loaded == validator.is_valid(raw), case


def test_a_declared_key_without_its_field_is_a_programming_error():
    """Built without the declaration, the nested table is one value, which Thing has no field for."""
    with pytest.raises(TypeError, match="Thing has no field for inner"):
        build(Thing, _read({"name": "a", "inner": {"depth": 1}}))


# A value per target of the cell: targets a and b have their own keys (a numbers its signals, b names them), c none
PER_TARGET = Table(
    "Signals per target.",
    {
        "signal": Key(
            "map",
            "a signal per target",
            per_name={
                "a": Key("integer", "the signal on a", low=1, high=8, expected="an a signal number 1..8"),
                "b": Key("string", "the signal on b", pattern="[a-z]+", expected="a name in small letters"),
            },
            per_target=True,
            lacking="{target} has no signals: take it out",
        ),
        "picked": Key("map", "where some have one", per_name={"a": Key("integer", "on a")}, per_target=True),
    },
)


def _per_target(raw: dict, targets: tuple[str, ...]) -> dict:
    return Loader(CellValidator("cell.toml"), targets=targets).table(PER_TARGET, raw, "io")


def test_a_per_target_map_has_an_entry_for_each_target_of_the_cell_checked_by_its_own_key():
    values = _per_target({"signal": {"a": 3, "b": "grip"}, "picked": {"a": 2}}, ("a", "b"))
    assert values == {"signal": {"a": 3, "b": "grip"}, "picked": {"a": 2}}
    assert _per_target({}, ("a", "b")) == {"signal": {}, "picked": {}}  # absent: no entries
    assert _per_target({"signal": {"b": "x"}}, ("b",))["signal"] == {"b": "x"}  # a target not in the cell: none


@pytest.mark.parametrize(
    ("raw", "targets", "says"),
    [
        ({"signal": {"a": 3}}, ("a", "b"), "io.signal.b: missing: the signal on b (every target of the cell names it)"),
        ({"signal": {"a": 9, "b": "x"}}, ("a", "b"), "io.signal.a: expected an a signal number 1..8, got the number 9"),
        ({"signal": {"a": True}}, ("a",), "io.signal.a: expected an a signal number 1..8, got a boolean"),
        ({"signal": {"b": "Grip"}}, ("b",), "io.signal.b: expected a name in small letters, got the string 'Grip'"),
        ({"signal": {"a": 1, "b": "x"}}, ("a",), "io.signal.b: unknown key; allowed: a"),
        ({"signal": {"a": 1}}, ("a", "c"), "io.signal: c has no signals: take it out"),
        ({"signal": 5}, ("a",), "io.signal: expected a table, got the number 5"),
        ({"picked": {"a": 1, "c": 2}}, ("a", "c"), "io.picked.c: unknown key; allowed: a"),  # c has none: passed over
    ],
)
def test_a_per_target_map_refuses_with_the_key_path(raw, targets, says):
    with pytest.raises(CellError) as info:
        _per_target(raw, targets)
    assert says in str(info.value)


def _edited(tmp_path, example: str, old: str, new: str):
    text = EXAMPLES[example].read_text(encoding="utf-8")
    assert text.count(old) >= 1
    text = text.replace(old, new, 1)
    path = tmp_path / "cell.toml"
    path.write_text(text, encoding="utf-8")
    line = next(i for i, row in enumerate(text.splitlines(), start=1) if new in row)
    return path, line


@pytest.mark.parametrize(
    ("example", "old", "new", "says"),
    [
        (
            "eur_pallet",
            "layers = 5 ",
            "layers = 0 ",
            "pallet[0].layers: expected a whole number in 1..200 (layers in the stack), got the number 0",
        ),
        (
            "eur_pallet",
            "timeout_s = 10.0",
            "timeout_s = 0.1",
            "pallet[0].io.timeout_s: must be in [0.5, 600] s (how long each wait lasts), got 0.1",
        ),
        (
            "belt_pick",
            "capture_mm = 3.0",
            "capture_mm = 51.0",
            "conveyor.pick.capture_mm: must be in (0, 50] mm (intercept: how far off the gripper may meet the part and "
            "still hold it), got 51",
        ),
        (
            "laser_tcp",
            "pin_radius_mm = 1.5",
            "pin_radius_mm = 26.0",
            "laser.pin_radius_mm: must be in [0.2, 25] mm (the calibrated pin's radius (a thinner pin is no target for "
            "the beams)), got 26",
        ),
    ],
)
def test_a_loaded_cell_names_the_line_of_the_key(tmp_path, example, old, new, says):
    path, line = _edited(tmp_path, example, old, new)
    with pytest.raises(CellError) as info:
        load_cell(path)
    assert str(info.value) == f"{path}: line {line}: {says}"


def test_the_second_pallet_of_a_cell_is_found_by_its_index(tmp_path):
    text = EXAMPLES["eur_pallet"].read_text(encoding="utf-8")
    second = text.index("[[pallet]]", text.index("[[pallet]]") + 1)
    edited = text[:second] + text[second:].replace("layers = 5 ", "layers = 0 ", 1)
    path = tmp_path / "cell.toml"
    path.write_text(edited, encoding="utf-8")
    line = edited[:second].count("\n") + edited[second:].split("layers = 0 ")[0].count("\n") + 1
    with pytest.raises(CellError, match=rf": line {line}: pallet\[1\]\.layers: "):
        load_cell(path)


TOML = """\
top = 1
[cell]
name = "a [b] # c"
targets = [
  "ur",   # ] not the end
  "kuka",
]
[cell.io]
output = { ur = 1 }
[[station]]
id = 1
[station.poses]
p1 = [0, 0, 0, 0, 0, 0]
[[station]]
id = 2
notes = '''
[not a header]
'''
"quoted key".x = 3
[[pallet]]
[pallet.io]
timeout_s = 2
"""


def test_key_lines_follow_headers_arrays_of_tables_and_multi_line_values():
    lines = key_lines(TOML)
    assert lines[("top",)] == 1 and lines[("cell",)] == 2 and lines[("cell", "targets")] == 4
    assert lines[("cell", "io", "output")] == 9 and lines[("station", 0, "poses", "p1")] == 13
    assert lines[("station", 1, "id")] == 15 and lines[("station", 1, "quoted key", "x")] == 19
    assert lines[("pallet", 0, "io", "timeout_s")] == 22
    assert ("not a header",) not in lines and ("kuka",) not in lines


@pytest.mark.parametrize(
    ("path", "line"),
    [
        ("cell.io.output.ur", 9),  # in an inline table: the table's line
        ("cell.targets[1]", 4),
        ("station[1].id", 15),  # every array counts from 0 in messages
        ("station[0].poses.p1", 13),
        ("pallet[0].io.timeout_s", 22),
        ("cell.motion.zone_mm", 2),  # not written: the nearest enclosing table
        ("spare", None),
    ],
)
def test_line_of_a_message_key_path(path, line):
    assert line_of(TOML, path) == line


def test_key_lines_read_quoted_keys_and_arrays_of_tables_as_toml_does():
    text = '[cell]\n"a\\"b" = 1\n\'c\\d\' = 2\n[[pallet]]\n[[pallet]]\n'
    assert tomllib.loads(text)["cell"] == {'a"b': 1, "c\\d": 2}
    lines = {("cell",): 1, ("cell", 'a"b'): 2, ("cell", "c\\d"): 3, ("pallet",): 4, ("pallet", 0): 4, ("pallet", 1): 5}
    assert key_lines(text) == lines


SIDES = Table(
    "A list chosen from fixed values.",
    {
        "sides": Key(
            "list",
            "the sides used",
            required=True,
            non_empty=True,
            values=Key("string", "a side", choices=("left", "right")),
        )
    },
)


@pytest.mark.parametrize(
    ("raw", "says"),
    [
        ({}, "demo.sides: missing: the sides used: 'left', 'right'"),
        ({"sides": []}, "demo.sides: expected at least one value (the sides used: 'left', 'right')"),
        ({"sides": "left"}, "demo.sides: expected a list from 'left', 'right', got the string 'left'"),
        ({"sides": [3]}, "demo.sides[0]: expected one of 'left', 'right' (a side), got the number 3"),
        ({"sides": ["up"]}, "demo.sides[0]: expected one of 'left', 'right' (a side), got 'up'"),
    ],
)
def test_a_message_about_a_chosen_value_lists_the_values_allowed(raw, says):
    with pytest.raises(CellError) as info:
        Loader(CellValidator("cell.toml")).table(SIDES, raw, "demo")
    assert str(info.value) == f"cell.toml: {says}"
