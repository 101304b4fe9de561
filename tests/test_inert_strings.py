"""Every string of a cell file is inert in every program: hostile text leaves the programs' structure as it was."""

from __future__ import annotations

import copy
import re
import tomllib
from dataclasses import replace
from functools import cache
from xml.etree import ElementTree

import pytest
from support.cells import EXAMPLES, is_configuration
from support.cells import structure as file_structure

from codegen.emit import EmitError
from codegen.generate import check_rendered
from codegen.model.cell import cell_from_dict
from codegen.model.validate import CellError
from codegen.render import render
from codegen.robot import arms

# Hostile text, after a tag naming the string it stands for (k<n>): first every character that could end a string,
# a comment or a line in one of the languages (quotes, backslash, CR, LF, the Unicode line and paragraph separators,
# NEL, NUL, ; ! # //), so that each falls within the shortest limit (80 characters); then the words that end a
# routine or a module, a declaration and a whole move of each language, Jinja's own braces, other controls and
# non-ASCII, and text far beyond every limit (identifiers, strings, comments).
PAYLOAD = (
    "\"'\\\r\n\u2028\u2029\x85\x00;!#//\t\x0b\x0c ENDPROC\nENDMODULE\nEND\nDEF evil()\nDECL INT evil\n  PROC evil()\n"
    "  movej([0, -1.57, 0, -1.57, 0, 0])\n  MoveJ p, v100, z10, tool0;\n{{ x }} {% if %} %s $OUT[1]=TRUE "
    "\u200b\u202e\u6c49\u00e9\ufeff" + "W" * 1100
)
_TAG = re.compile(r"k(\d+)(?!\d)")


def _catalogue() -> dict[str, dict]:
    return {arm["model"]: arm for arm in tomllib.loads(arms.CATALOGUE.read_text(encoding="utf-8"))["arm"]}


def with_custom_arms(data: dict) -> dict:
    """The cell with each catalogue arm written out as a custom arm (its model, vendor and source then strings of
    the cell file)."""
    out = copy.deepcopy(data)
    robot = out.get("cell", {}).get("robot", {})
    catalogue = _catalogue()
    for target in out["cell"]["targets"]:
        if isinstance(robot.get(target), str):
            robot[target] = copy.deepcopy(catalogue[robot[target]])
    return out


def strings(value) -> set[str]:
    """Every string of a TOML document: each table's keys and each string value (in arrays too)."""
    if isinstance(value, str):
        return {value}
    if isinstance(value, dict):
        return set(value).union(*(strings(v) for v in value.values()))
    if isinstance(value, list):
        return set().union(*(strings(v) for v in value))
    return set()


def renamed(value, new: dict[str, str]):
    """The document with each string in `new` (a key or a value, wherever it stands) replaced."""
    if isinstance(value, str):
        return new.get(value, value)
    if isinstance(value, dict):
        return {new.get(k, k): renamed(v, new) for k, v in value.items()}
    if isinstance(value, list):
        return [renamed(v, new) for v in value]
    return value


def load(data: dict):
    return cell_from_dict(data, source="hostile.toml", sha256="0" * 64)


@cache
def _custom_armed(example: str):
    """The example with its arms written out as custom arms, clean: one Cell per process, so its proofs serve every
    test that renders it (cells are frozen)."""
    return load(with_custom_arms(tomllib.loads(EXAMPLES[example].read_text(encoding="utf-8"))))


def structure(files) -> list[tuple]:
    """Each program file's parse tree's shape; a configuration file (XML) its elements and their attributes' names."""
    return [file_structure(f.relpath, f.text) for f in files]


def hostile_render(data: dict, payload: str) -> tuple[list, dict[str, str]]:
    """Every string of the cell replaced at once by its tag and the payload, less those refused: the loader's
    refusals (exit 2) first, one string at a time, then the generator's (EmitError: exit 2), until it renders.
    Returns the files and each string's fate ("loader", "generate" or "rendered")."""
    sites = sorted(strings(data))
    hostile = {s: f"k{i}{payload}" for i, s in enumerate(sites)}
    fate: dict[str, str] = {}
    for s in sites:
        try:
            load(renamed(data, {s: hostile[s]}))
        except CellError:
            fate[s] = "loader"
    while True:
        accepted = {s: text for s, text in hostile.items() if s not in fate}
        try:
            files = render(load(renamed(data, accepted)))
        except (CellError, EmitError) as exc:
            tag = _TAG.search(str(exc))
            assert tag is not None, f"refused, naming no hostile string: {exc}"
            site = sites[int(tag.group(1))]
            assert site not in fate, f"{site!r} refused twice: {exc}"
            fate[site] = "loader" if isinstance(exc, CellError) else "generate"
            continue
        fate.update(dict.fromkeys(accepted, "rendered"))
        return files, fate


def _flat(tree, out: list) -> list:
    out.append(tree[0])
    for child in tree[1:]:
        _flat(child, out)
    return out


def first_difference(got: tuple, want: tuple) -> str:
    a, b = _flat(got, []), _flat(want, [])
    i = next((i for i, (x, y) in enumerate(zip(a, b, strict=False)) if x != y), min(len(a), len(b)))
    return f"at node {i}: {a[max(0, i - 4) : i + 4]} where the clean cell has {b[max(0, i - 4) : i + 4]}"


def names(value) -> set[str]:
    """The values of every `name` and `model` key of a TOML document (the cell's, the stations', the pallets', the
    arms'), less the names of an arm's link shapes (the clearance check's words: no program prints them)."""
    if isinstance(value, dict):
        own = {v for k, v in value.items() if k in ("name", "model") and isinstance(v, str)}
        return own.union(*(names(v) for k, v in value.items() if k != "links"))
    if isinstance(value, list):
        return set().union(*(names(v) for v in value))
    return set()


@pytest.mark.parametrize("example", sorted(EXAMPLES))
def test_hostile_strings_leave_every_program_as_it_was(example):
    """Each example with its arms written out as custom arms (so their model is the cell's text): every string of
    the file, key or value, replaced by hostile text at once, less those the loader or the generator refuses
    (exit 2). Every program still parses and has the clean cell's structure (the grammar's rules and token types
    in order: the same routines, declarations, statements and moves)."""
    data = with_custom_arms(tomllib.loads(EXAMPLES[example].read_text(encoding="utf-8")))
    clean = render(_custom_armed(example))
    want = structure(clean)
    files, fate = hostile_render(data, PAYLOAD)
    check_rendered(files)  # what generate checks before it writes: ASCII, a final newline, the grammar
    assert len(files) == len(clean)
    for f, got, expected in zip(files, structure(files), want, strict=True):
        if got != expected:
            pytest.fail(f"{f.relpath}: not the clean cell's structure, {first_difference(got, expected)}")
    rendered = {s for s, what in fate.items() if what == "rendered"}
    assert names(data) <= rendered, "every name and arm model must reach the programs as hostile text"


def test_a_cell_string_in_a_channel_configuration_is_xml_escaped():
    """The KUKA channel's XML prints one string of the cell, the vision PC's address, XML-escaped (the loader
    takes only an IPv4 address there; the escape keeps any text inert): hostile text past the loader, with XML's
    own markup added, leaves the configuration's elements as they were and reads back as its printable ASCII."""
    cell = _custom_armed("agv_machine_tending")
    hostile_ip = PAYLOAD + '--><!-- <ELEMENT Tag="x"/> ]]> &amp; &#0;'
    clean = [f for f in render(cell, ["kuka"]) if is_configuration(f.relpath)]
    files = render(replace(cell, vision=replace(cell.vision, ip=hostile_ip)), ["kuka"])
    configurations = [f for f in files if is_configuration(f.relpath)]
    check_rendered(files)
    assert len(configurations) == len(clean) == 1 and structure(configurations) == structure(clean)
    ip = ElementTree.fromstring(configurations[0].text).findtext("CONFIGURATION/EXTERNAL/IP")
    assert ip == "".join(ch if " " <= ch <= "~" else "?" for ch in hostile_ip)


# The reproducer: an arm's model that, printed as it is, is a statement of the target's language.
STATEMENTS = {
    "ur": "MyUR\n  movej([0, -1.57, 0, -1.57, 0, 0])\n  #",
    "kuka": "MyKR\nDECL INT EVIL=1\n;",
    "abb": "MyIRB\n  PROC evil()\n  ENDPROC\n  !",
}


def _example_targets(example: str) -> list[str]:
    return tomllib.loads(EXAMPLES[example].read_text(encoding="utf-8"))["cell"]["targets"]


@pytest.mark.parametrize(
    ("example", "target"),
    [(e, t) for e in sorted(EXAMPLES) for t in sorted(STATEMENTS) if t in _example_targets(e)],  # its programs' own
)
def test_an_arm_model_that_is_a_statement_adds_none(example, target):
    data = with_custom_arms(tomllib.loads(EXAMPLES[example].read_text(encoding="utf-8")))
    want = structure(render(_custom_armed(example), [target]))
    data["cell"]["robot"][target]["model"] = STATEMENTS[target]
    files = render(load(data), [target])
    for f, got, expected in zip(files, structure(files), want, strict=True):
        assert got == expected, f"{f.relpath}: {first_difference(got, expected)}"


# --- names the program itself uses, and the language's own ------------------------------------------------


def _example(name: str, **edits) -> dict:
    """An example's TOML tables with edits: {"a.b.c": value} sets a key (list indices as numbers)."""
    data = tomllib.loads(EXAMPLES[name].read_text(encoding="utf-8"))
    for path, value in edits.items():
        *parents, last = [int(p) if p.isdigit() else p for p in path.split(".")]
        table = data
        for key in parents:
            table = table[key]
        table[last] = value
    return data


@pytest.mark.parametrize(
    ("example", "key", "value", "own"),
    [
        ("laser_tcp", "laser.beam_x.abb", "lsr_guess", "lsr_guess"),  # the laser program's tooldata
        ("laser_tcp", "laser.beam_y.abb", "LSR_GUESS", "LSR_GUESS"),  # RAPID ignores case
        ("testmat_pallet", "cell.io.output.abb", "stack_tool", "stack_tool"),  # the pallet program's tooldata
        ("agv_machine_tending", "cell.io.output.abb", "vis_stop", "vis_stop"),  # the station program's routine
        ("laser_tcp", "laser.beam_x.abb", "lsr_edge", "lsr_edge"),  # a name verify reads (targets/abb.toml)
    ],
)
def test_a_signal_named_like_the_programs_own_data_is_refused(example, key, value, own):
    with pytest.raises(EmitError, match=rf"{re.escape(key)} and the program's own name {own} both map"):
        render(load(_example(example, **{key: value})), ["abb"])


@pytest.mark.parametrize("value", ["TRUE", "false", "tool0", "v100", "Z50", "fine", "wobj0", "load0", "num", "MoveL"])
def test_a_signal_named_like_a_word_or_predefined_name_of_rapid_is_refused(value):
    with pytest.raises(EmitError, match=rf"laser.beam_x.abb: '{value}' is a word or predefined name of"):
        render(load(_example("laser_tcp", **{"laser.beam_x.abb": value})), ["abb"])


@pytest.mark.parametrize(
    ("target", "name", "ident"),
    [
        ("abb", "v100", "v100_"),  # predefined speeddata
        ("abb", "tool0", "tool0_"),
        ("abb", "MODULE", "MODULE_"),  # a word RAPID reserves
        ("kuka", "BAS", "BAS_"),  # a built-in routine
        ("kuka", "TOOL_DATA", "TOOL_DATA_"),  # a system array
        ("kuka", "TRUE", "TRUE_"),
        ("kuka", "$OUT[1]", "OUT_1"),  # a system variable's $ never reaches an identifier
        ("ur", "textmsg", "textmsg_"),  # a built-in function
        ("ur", "movej", "movej_"),
    ],
)
def test_a_cell_named_like_a_predefined_name_gets_another_identifier(target, name, ident):
    program = render(load(_example("agv_machine_tending", **{"cell.name": name})), [target])[0]
    assert program.relpath.split("/")[-1].startswith(ident.lower() + "."), program.relpath
    assert re.search(rf"^(MODULE|DEF|def) {ident}\b", program.text, re.MULTILINE), program.relpath


@pytest.mark.parametrize(
    ("target", "key", "value", "own"),
    [
        ("ur", "pallet.0.name", "grip", "pal_grip"),  # the pallet program's gripper routine
        ("kuka", "pallet.0.name", "frame", "PAL_FRAME"),  # the pallet frame (each pallet's counters: PAL_<name>_LAYER)
        ("abb", "cell.name", "main", "main"),  # the station program's entry routine
    ],
)
def test_a_cell_name_mapped_onto_the_programs_own_is_refused(target, key, value, own):
    data = _example("agv_machine_tending" if key == "cell.name" else "testmat_pallet", **{key: value})
    with pytest.raises(EmitError, match=rf"the program's own name {own} both map to the identifier {own}"):
        render(load(data), [target])


def test_the_refusal_is_exit_2_through_generate(tmp_path):
    from click.testing import CliRunner

    from codegen.cli import main

    text = EXAMPLES["laser_tcp"].read_text(encoding="utf-8").replace('abb = "diLaserX"', 'abb = "lsr_guess"')
    (tmp_path / "cell.toml").write_text(text, encoding="utf-8")
    result = CliRunner().invoke(main, ["generate", str(tmp_path / "cell.toml"), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "laser.beam_x.abb and the program's own name lsr_guess both map to the identifier lsr_guess" in result.output
    assert "Traceback" not in result.output and not (tmp_path / "out").exists()


def test_the_generators_own_names_are_its_code_not_its_comments():
    from codegen.emit import own_names

    abb = own_names("abb")
    assert {"lsr_guess", "stack_tool", "cnv_hold", "vis_stop", "main", "giCnvSeq", "lsr_edge"} <= abb
    assert {"PAL_FRAME", "VIS_SIGNAL"} <= own_names("kuka")
    assert {"vis_stop", "pal_grip", "p"} <= own_names("ur")  # p: a pose literal p[...]
    assert not {"the", "calibration", "arm", "gripper"} & (abb | own_names("ur") | own_names("kuka"))


# --- the one path: what the templates may print ----------------------------------------------------------------


def _station_plan(target: str):
    from codegen.controllers import get_target
    from codegen.render import plans, shared_context

    cell = load(with_custom_arms(tomllib.loads(EXAMPLES["agv_machine_tending"].read_text(encoding="utf-8"))))
    return cell, get_target(target), plans(cell, get_target(target))[0], shared_context(cell, get_target(target))


@pytest.mark.parametrize(
    ("target", "key", "value", "template", "shown"),
    [
        ("ur", ("robot", "model"), "UR10e", "ur/body.j2", r"'UR10e' \(str\)"),  # a cell's text, as it was printed
        ("abb", ("robot", "model"), "IRB 1600", "abb/program.mod.j2", r"'IRB 1600' \(str\)"),
        ("kuka", ("speeds", "joint_percent"), 25.0, "kuka/program.src.j2", r"25.0 \(float\)"),  # a number not formatted
        ("ur", ("cell", "comment"), True, "ur/body.j2", r"True \(bool\)"),
        ("abb", ("cell", "source"), None, "abb/program.mod.j2", r"None \(NoneType\)"),
    ],
)
def test_a_value_that_did_not_pass_through_the_emitter_is_refused(target, key, value, template, shown):
    from codegen.render import UnmarkedText, render_plan

    cell, target, plan, shared = _station_plan(target)
    shared[key[0]][key[1]] = value
    with pytest.raises(UnmarkedText, match=rf"{re.escape(template)}: the template prints {shown}"):
        render_plan(cell, target, plan, shared=shared)


@pytest.mark.parametrize(
    ("source", "values", "printed"),
    [
        ('{{ "a" ~ x ~ 1 }}', {"x": "b"}, None),  # `~` of a plain string
        ('{{ xs | join(", ") }}', {"xs": ["a"]}, None),
        ("{{ x | upper }}", {"x": "a"}, None),
        ("{{ x[1:] }}", {"x": "ab"}, None),
        ('{{ "a" ~ x ~ 1 }}', {"x": "b", "code": True}, "ab1"),
        ('{{ xs | join(", ") }}|{{ xs | map("upper") | join }}', {"xs": ["a", "b"], "code": True}, "a, b|AB"),
        ("{{ x[1:] | upper }}", {"x": "ab", "code": True}, "B"),
        ('{% macro m(y) %}<{{ y }}>{% endmacro %}{{ m(x) ~ m("t") }}', {"x": "a", "code": True}, "<a><t>"),
        ('{{ "e" if x }}{{ n * 2 }}', {"x": False, "n": 3, "code": True}, "6"),
    ],
)
def test_the_templates_own_text_stays_printable_and_nothing_else_is(source, values, printed):
    from codegen.emit import owned
    from codegen.render import UnmarkedText, environment

    template = environment().from_string(source)
    if values.pop("code", False):
        assert template.render(**owned(values)) == printed
    else:
        with pytest.raises(UnmarkedText, match="did not pass through the emitter"):
            template.render(**values)


def test_only_the_emitter_and_the_renderer_make_printable_text():
    """Code is made in codegen/emit.py (and by codegen/render.py for the templates' own text); `owned` marks the
    generator's facts, never a cell's value."""
    package = EXAMPLES["agv_machine_tending"].parents[1]
    makers = sorted(
        str(path.relative_to(package))
        for path in package.rglob("*.py")
        if re.search(r"\bCode\(", path.read_text(encoding="utf-8"))
    )
    assert makers == ["emit.py", "render.py"]
    for path in package.rglob("*.py"):
        for line in path.read_text(encoding="utf-8").splitlines():
            assert not re.search(r"\bowned\([^)]*\bcell\b", line), f"{path.name}: {line.strip()}"


def test_a_signal_and_a_name_of_the_cell_share_the_programs_names():
    """The cell's signals are claimed in every program before the names it maps (one namespace per program)."""
    data = _example("agv_machine_tending", **{"cell.io.output.abb": "st_lathe_1"})
    with pytest.raises(
        EmitError, match=r"abb: station\[0\] 'lathe_1' and cell.io.output.abb both map to the identifier"
    ):
        render(load(data), ["abb"])
