"""The example cells every kind's tests run on, a two-station cell with any names, and hostile text."""

from __future__ import annotations

from functools import cache
from pathlib import Path

from hypothesis import strategies as st
from lark import Token

from codegen.controllers import target_names
from codegen.model.cell import example_cells, load_cell

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = {path.stem: path for path in example_cells()}  # together they use every kind


@cache
def example(name: str):
    """An example cell, loaded once per test session (cells are frozen)."""
    return load_cell(EXAMPLES[name])


@cache
def kind_targets() -> tuple[tuple[str, str, str], ...]:
    """(kind, target, example cell) for every kind's programs of every target in the examples: the first example
    cell that has them, read from its sections without planning (a kind writes programs only from its own section,
    so these pairs hold every pair with programs; a pair without any fails the kinds' render test, which asserts
    them: tests/kinds/kind_base.py)."""
    out: dict[tuple[str, str], str] = {}
    for name in EXAMPLES:
        cell = example(name)
        for target in cell.targets:
            for kind in cell.kinds:
                if kind in cell.sections:
                    out.setdefault((kind, target), name)
    return tuple((kind, target, cell) for (kind, target), cell in sorted(out.items()))


HOSTILE = st.lists(
    st.sampled_from(
        [
            '"',
            "'",
            "\n",
            "\r",
            ";",
            "!",
            "#",
            "//",
            "%d",
            "END",
            "ENDPROC",
            "end",
            "\\",
            "{",
            "}",
            "[",
            "]",
            ":=",
            "é",
            "汉",
            "\x00",
            "\t",
            " ",
            "a",
            "Z",
            "_",
            "9",
            "$",
        ]
    ),
    min_size=1,
    max_size=60,
).map("".join)


def cell_text(station_names: list[str], pose_names: list[str] | None = None) -> str:
    """A two-station cell with the given names (TOML-escaped), same numbers every time."""

    def q(text: str) -> str:
        return '"' + "".join(c if c.isprintable() and c not in '"\\' else f"\\u{ord(c):04x}" for c in text) + '"'

    pose_names = pose_names or ["approach", "work"]
    stations = []
    for i, name in enumerate(station_names, start=1):
        stations.append(
            f"[[station]]\nid = {i}\nname = {q(name)}\nmark = [{600 + i}.5, -250.0, {i}.0]\n[station.poses]\n"
            f"{q(pose_names[0])} = [650.0, -100.0, 400.0, 90.0, 0.0, 180.0]\n"
            f"{q(pose_names[1])} = [700.0, -100.0, 300.0, 90.0, 10.0, 180.0]\n"
        )
    return (
        f'[cell]\nname = "bench"\ntargets = {list(target_names())!r}\n[cell.camera]\nangle_sign = -1\n'
        "[cell.limits]\nmax_shift_mm = 10.0\nmax_rotation_deg = 10.0\n" + "\n".join(stations)
    )


def shape(tree) -> tuple:
    """The statement structure of a parse tree: rule names and token types, no values."""
    if isinstance(tree, Token):
        return (tree.type,)
    if tree is None:
        return ("-",)
    return (tree.data, *(shape(c) for c in tree.children))


def is_configuration(relpath: str) -> bool:
    """A file a program reads when it runs, in a format of its own (a KUKA.EthernetKRL channel's .xml), not code."""
    from codegen.dialects import dialects

    return relpath.lower().endswith(tuple(s for d in dialects().values() for s in d.configurations))


def structure(relpath: str, text: str) -> tuple:
    """A generated file's structure: a program's or data file's parse tree (shape); a configuration's XML elements
    in document order, each with its attributes' names (a cell's text that changed them would show)."""
    from xml.etree import ElementTree

    from codegen.dialects import parse_program

    if is_configuration(relpath):
        return tuple((e.tag, tuple(sorted(e.attrib))) for e in ElementTree.fromstring(text).iter())
    return shape(parse_program(relpath, text, positions=False))


def replace_once(text: str, old: str, new: str) -> str:
    assert old in text, f"{old!r} not in program"
    return text.replace(old, new, 1)


# a small point-station cell of every target
MINIMAL_CELL = """\
[cell]
name = "bench"
targets = {TARGETS}
pose_format = "xyzabc"
[cell.camera]
angle_sign = -1
[cell.limits]
max_shift_mm = 10.0
max_rotation_deg = 10.0
[[station]]
id = 1
name = "lathe_1"
mark = [600.0, -250.0, 2.0]
[station.poses]
approach = [650.0, -100.0, 400.0, 90.0, 0.0, 180.0]
chuck = [700.0, -100.0, 300.0, 90.0, 0.0, 180.0]
[[station]]
id = 2
name = "mill_1"
mark = [640.0, 210.0, 0.0]
[station.poses]
vise = [700.0, 50.0, 260.0, -90.0, 15.0, 180.0]
""".replace("{TARGETS}", repr(list(target_names())).replace("'", '"'))


def unstacking_testmat_text() -> str:
    """Source 004's test cell unstacking (no bundled cell unstacks on UR): no slip sheets, Q clear waited for, above
    Q high enough to clear a box lying there; Q where the bundled cell has it."""
    text = EXAMPLES["testmat_pallet"].read_text(encoding="utf-8")
    lines = [line for line in text.splitlines() if not line.startswith(("slip_sheet =", "sheet_ready ="))]
    text = "\n".join(lines).replace("part_present = ", "place_clear = ")
    text = text.replace("pick_lift = 30.0", 'pick_lift = 40.0\nmode = "unstack"')
    assert 'mode = "unstack"' in text and "pick = [600.0, 300.0, 50.0," in text
    return text


def unstacking_clear_q_text() -> str:
    """Source 004's test cell unstacking, its Q moved away from the pallet: a box held at the start is carried from
    home to above Q, and from the bundled Q that joint move swings it through the full stack (generate refuses it)."""
    text = unstacking_testmat_text().replace("pick = [600.0, 300.0, 50.0,", "pick = [450.0, 350.0, 50.0,")
    assert "pick = [450.0, 350.0, 50.0," in text
    return text
