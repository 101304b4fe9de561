"""The cell file's key lines: every key tomllib reads is found on the line that writes it, and only those."""

from __future__ import annotations

import tomllib

import pytest

from codegen.model.lines import key_lines
from codegen.reports.cell_lines import entry_of, key_under
from tests.support.cells import EXAMPLES

TEXT = '''\
# a comment = not a key
[cell]
name = "bench"   # a comment
targets = [
  "ur",
  "kuka",  # [not a table]
]
grid = [
  [1, 2],
  [3, 4],
]
note = """
[[station]]
fake = 1
"""
[cell.limits]
max_shift_mm = 10.0
"quoted key" = 1
'lit.eral' = 2
a.b = 3

[[station]]
id = 7
name = "lathe"
[station.poses]
approach = [650.0, -100.0, 400.0, 90.0, 0.0, 180.0]
chuck = [700.0, -100.0, 300.0,
         90.0, 0.0, 180.0]

[[station]]
id = 8
name = "mill"
[station.poses]
chuck = [1, 2, 3, 4, 5, 6]
'''


def test_each_key_on_its_own_line():
    lines = key_lines(TEXT)
    text = TEXT.splitlines()
    expected = {
        ("cell", "name"): 'name = "bench"',
        ("cell", "targets"): "targets = [",
        ("cell", "note"): 'note = """',
        ("cell", "limits", "max_shift_mm"): "max_shift_mm = 10.0",
        ("cell", "limits", "quoted key"): '"quoted key" = 1',
        ("cell", "limits", "lit.eral"): "'lit.eral' = 2",
        ("cell", "limits", "a", "b"): "a.b = 3",
        ("station", 0, "id"): "id = 7",
        ("station", 0, "poses", "chuck"): "chuck = [700.0, -100.0, 300.0,",
        ("station", 1, "poses", "chuck"): "chuck = [1, 2, 3, 4, 5, 6]",
    }
    for path, line in expected.items():
        assert text[lines[path] - 1].startswith(line), path
    assert ("station", 0, "fake") not in lines and ("station", 2) not in lines  # inside a string, not a table
    assert ("cell", "targets", "kuka") not in lines and ("1",) not in lines  # inside an array


def _leaves(data, path=()):
    if isinstance(data, dict):
        for key, value in data.items():
            yield (*path, key)
            yield from _leaves(value, (*path, key))
    elif isinstance(data, list) and data and all(isinstance(v, dict) for v in data):
        for i, value in enumerate(data):
            yield from _leaves(value, (*path, i))


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_every_key_of_the_example_cells_is_found_where_it_is_written(name):
    text = EXAMPLES[name].read_text(encoding="utf-8")
    data = tomllib.loads(text)
    lines = key_lines(text)
    rows = text.splitlines()
    for path in _leaves(data):
        if path in lines:
            row = rows[lines[path] - 1]
            assert str(path[-1]) in row, (path, row)
        else:  # written inside an inline table or as a table header's part: its parent is found
            assert any(path[:n] in lines for n in range(len(path) - 1, 0, -1)), path
    for path in lines:  # nothing found that tomllib does not read
        value = data
        for part in path:
            value = value[part]


def test_the_entry_a_case_names_and_the_key_under_it():
    data, lines = tomllib.loads(TEXT), key_lines(TEXT)
    assert entry_of(data, "random station 8 reading (1, 2, 3)") == ("station", 1)
    assert entry_of(data, "station lathe reading") == ("station", 0)
    assert entry_of(data, "station 9 reading") is None
    assert key_under(lines, ("station", 1), "chuck") == ("station", 1, "poses", "chuck")
    assert key_under(lines, (), "chuck") is None  # two stations have one: not told apart


def test_a_moves_key_is_the_pose_not_what_the_gripper_does_there():
    text = '[[station]]\nid = 1\n[station.poses]\nchuck = [1, 2, 3, 0, 0, 0]\n[station.gripper]\nchuck = "release"\n'
    data, lines = tomllib.loads(text), key_lines(text)
    assert key_under(lines, ("station", 0), "chuck") is None  # by the name alone: two keys
    assert key_under(lines, ("station", 0), "chuck", data) == ("station", 0, "poses", "chuck")
