"""The two registries: controllers from targets/*.toml, languages from codegen/dialects/<d>/; the layout."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path
from string import Formatter

import pytest
from setuptools import find_packages

from codegen import controllers
from codegen.controllers import TargetError, get_target, target_names
from codegen.dialects import dialect_of_suffix, dialects, get_dialect
from codegen.kinds.station.section import stations_of
from codegen.protocol import installed_kinds

REPO = Path(__file__).resolve().parents[1]
CODE = [p for p in (REPO / "codegen").rglob("*.py")] + list((REPO / "templates").rglob("*.j2"))


def _readers(key: str, table: str = "target") -> list[Path]:
    """Files that read a target fact (`target.key`, also through another name for the target) or a
    [program] fact (`program.key`, `program["key"]`, `program.get("key"`); declarations excluded."""
    if table == "program":
        pattern = re.compile(rf'program\.{key}\b|program\["{key}"\]|program\.get\("{key}"')
    else:
        pattern = re.compile(rf'\.{key}\b|facts\["{key}"\]')
    out = []
    for path in CODE:
        text = path.read_text(encoding="utf-8")
        if path.name == "controllers.py":
            text = "\n".join(line for line in text.splitlines() if not re.match(rf'\s+"?{key}"?:', line))
        if pattern.search(text):
            out.append(path)
    return out


def test_targets_are_discovered_from_their_files():
    assert set(target_names()) == {p.stem for p in (REPO / "targets").glob("*.toml")}
    for name in target_names():
        target = get_target(name)
        assert target.name == name and target.dialect in dialects()


@pytest.mark.parametrize("path", sorted((REPO / "targets").glob("*.toml")), ids=lambda p: p.stem)
def test_every_target_fact_is_read_by_code(path):
    """Every fact of a target is read: a top-level key or a [program] key by some code; a kind's own table
    [program.<kind>] is read by the kind (the registry refuses a table no kind has, and keys the kind does not
    declare), and each key it declares is read in the kind's own package."""
    facts = tomllib.loads(path.read_text(encoding="utf-8"))
    unread = [key for key in facts if key != "program" and not _readers(key)]
    own = set(installed_kinds())
    unread += [f"program.{key}" for key in facts["program"] if key not in own and not _readers(key, "program")]
    assert not unread, f"{path.name}: facts no code reads (make them comments): {unread}"


@pytest.mark.parametrize("name", sorted(installed_kinds()))
def test_every_fact_a_kind_declares_is_read_in_its_package(name):
    kind = installed_kinds()[name]
    package = REPO / "codegen" / "kinds" / name
    text = "\n".join(p.read_text(encoding="utf-8") for p in package.rglob("*.py"))
    text += "\n".join(p.read_text(encoding="utf-8") for p in (REPO / "templates").rglob(f"kinds/{name}*.j2"))
    unread = [key for key in kind.target_keys if not re.search(rf'\["{key}"\]|\.get\("{key}"|\b{key}\b', text)]
    assert not unread, f"{name}: [program.{name}] keys its package never reads: {unread}"


def test_the_key_check_can_fail():
    assert _readers("joint_move", "program")
    assert not _readers("no_code_reads_this_fact", "program")
    assert not _readers("mark", "program")  # a common word elsewhere, not a program fact


def test_an_unknown_or_missing_target_key_is_refused(tmp_path, monkeypatch):
    text = (REPO / "targets" / "ur.toml").read_text(encoding="utf-8")
    (tmp_path / "ur.toml").write_text(text.replace('title = "', 'vision = "x"\ntitle = "'), encoding="utf-8")
    with pytest.raises(TargetError, match="vision: unknown key"):
        controllers._load(tmp_path / "ur.toml")
    (tmp_path / "ur.toml").write_text(re.sub(r"\nstring_max = .*", "", text), encoding="utf-8")
    with pytest.raises(TargetError, match="string_max: missing"):
        controllers._load(tmp_path / "ur.toml")
    (tmp_path / "ur.toml").write_text(text.replace("joint_move = ", "joint_mvoe = "), encoding="utf-8")
    with pytest.raises(TargetError, match=r"program\.joint_mvoe: unknown key"):
        controllers._load(tmp_path / "ur.toml")
    wrong_type = text.replace("station_register = 24", "station_register = true")
    (tmp_path / "ur.toml").write_text(wrong_type, encoding="utf-8")
    with pytest.raises(TargetError, match=r"program\.station_register: expected int"):
        controllers._load(tmp_path / "ur.toml")


def test_the_example_cells_use_every_kind():
    from codegen.kinds.station.mode import modes
    from codegen.model.cell import example_cells, load_cell

    used, modes_used = set(), set()
    for path in example_cells():
        cell = load_cell(path)
        used |= set(cell.sections)
        modes_used |= {s.mode for s in stations_of(cell)}
    assert used == set(installed_kinds())
    assert modes_used == set(modes())


def test_every_file_suffix_has_one_dialect():
    for name in target_names():
        target = get_target(name)
        dialect = get_dialect(target.dialect)
        for suffix in target.suffixes:
            assert dialect_of_suffix(suffix) is dialect
            assert suffix in dialect.suffixes + dialect.companions + dialect.configurations


def test_kinds_are_registered_with_a_template_per_target():
    """Each station mode has its partial of the station program per target (kinds/station_<mode>.j2); a kind with
    programs of its own has a template for each file its [program.<kind>] table names (targets without the table
    write none of them): the pattern with {<kind>} as the kind's name and any other placeholder {x} as <kind>_x."""
    from codegen.kinds.station.mode import modes

    assert set(installed_kinds()) == {"station", "pallet", "conveyor", "laser"}
    assert set(modes()) == {"point", "frame"}
    for name in target_names():
        for mode in modes():
            assert (REPO / "templates" / name / "kinds" / f"station_{mode}.j2").is_file(), (name, mode)
        for kind_name, kind in installed_kinds().items():
            for pattern in kind.facts(get_target(name)).get("files", []):
                fields = {f for _, f, _, _ in Formatter().parse(pattern) if f}
                template = pattern.format(**{f: kind_name if f == kind_name else f"{kind_name}_{f}" for f in fields})
                assert (REPO / "templates" / name / "kinds" / f"{template}.j2").is_file(), (name, template)


def test_every_package_is_installed():
    pyproject = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))
    listed = set(pyproject["tool"]["setuptools"]["packages"])
    found = set(find_packages(str(REPO), include=["codegen*"]))
    assert found <= listed, f"packages missing from pyproject.toml: {sorted(found - listed)}"


def test_a_controller_is_named_only_in_its_own_files():
    """Outside targets/kuka.toml, templates/kuka/, codegen/dialects/krl/ and tests, no source names KUKA or KRL."""
    name = "kuka"
    target = get_target(name)
    words = {"kuka", "KUKA", "krl", "KRL"}
    # the arms' own conventions: the families' parameters and each vendor's configuration bits
    own = (
        REPO / "codegen" / "dialects" / target.dialect,
        REPO / "templates" / name,
        REPO / "codegen" / "robot" / "config.py",
        REPO / "codegen" / "robot" / "opw.py",
    )
    offenders = []
    for path in (REPO / "codegen").rglob("*.py"):
        if path in own or any(folder in path.parents for folder in own):
            continue
        text = path.read_text(encoding="utf-8")
        for word in words:
            if re.search(rf"\b{re.escape(word)}\b", text):
                offenders.append(f"{path.relative_to(REPO)}: {word}")
    assert not offenders, offenders


def _naming(word: str, bare: bool) -> re.Pattern:
    """How a source names a kind or a station mode: its package or module path, its classes, a lookup or a
    comparison by its name, a table declared for it; with `bare`, the name as a word at all."""
    title = word.capitalize()
    forms = [
        rf"\b(kinds|modes)[./]{word}\b",
        rf"\b{title}(Kind|Mode|Spec|Case|Section)\b",
        rf"(\b(mode|kind)\s*(==|!=)|\bget_(kind|mode)\(|\b(sections|settings|modes\(\)|kinds\(\))(\[|\.get\())\s*[\"']{word}[\"']",
        rf"\bkinds=\([^)]*[\"']{word}[\"']",
    ]
    if bare:
        forms.append(rf"\b{word}s?\b")
    return re.compile("|".join(forms), 0 if not bare else re.IGNORECASE)


def _names_outside(word: str, own: tuple[Path, ...], template_prefixes: tuple[str, ...], bare: bool) -> list[str]:
    pattern = _naming(word, bare)
    offenders = []
    for path in [*(REPO / "codegen").rglob("*.py"), *(REPO / "templates").rglob("*.j2")]:
        if path in own or any(folder in path.parents for folder in own) or path.name.startswith(template_prefixes):
            continue
        if REPO / "codegen" / "dialects" in path.parents:
            continue
        if pattern.search(path.read_text(encoding="utf-8")):
            offenders.append(f"{path.relative_to(REPO)}: {word}")
    return offenders


def test_a_program_kind_is_named_only_in_its_own_files():
    """Outside its package codegen/kinds/<kind>/ and its templates templates/<t>/kinds/<kind>.*.j2 and <kind>_*.j2,
    no source names a kind (cell, render, generate, verify and cli loop over the registry): not its package, its
    classes, a lookup or comparison by its name. The dialects are left out: a language's own built-ins carry their
    manual's words (URScript's track_conveyor_linear). A kind whose name is no word of the cell file's own
    vocabulary is held to more: its name appears nowhere else at all; the station kind's name is the cell file's
    [[station]] table and the word every program's operator messages use."""
    from codegen.kinds.station.keys import NAME

    offenders = []
    for word in sorted(installed_kinds()):
        own = (REPO / "codegen" / "kinds" / word,)
        offenders += _names_outside(word, own, (f"{word}.", f"{word}_"), bare=word != NAME)
    assert not offenders, offenders


def test_a_station_mode_is_named_only_in_its_own_files():
    """A station mode is one module codegen/kinds/station/modes/<mode>.py (with its helpers in
    codegen/kinds/station/<mode>/) and its partial templates/<t>/kinds/station_<mode>.j2: no other source names it
    (its package, its classes, a lookup, comparison or table by its name). The shared station code asks the
    registry of modes."""
    from codegen.kinds.station.mode import modes

    offenders = []
    station = REPO / "codegen" / "kinds" / "station"
    for word in sorted(modes()):
        own = (station / "modes" / f"{word}.py", station / word)
        offenders += _names_outside(word, own, (f"station_{word}.",), bare=False)
    assert not offenders, offenders


def test_the_naming_check_can_fail():
    assert _naming("frame", bare=False).search('if station.mode == "frame":')
    assert _naming("frame", bare=False).search("from codegen.kinds.station.modes.frame import FrameSpec")
    assert _naming("point", bare=False).search('kinds=("point", "frame")')
    assert _naming("station", bare=False).search('cell.sections.get("station")')
    assert not _naming("frame", bare=False).search('"frame": emitter.pose(frame)')  # a pallet's own key
    assert not _naming("point", bare=False).search('if role == "point":')  # a row of a TCP calibration
    assert _naming("pallet", bare=True).search("the pallets of the cell")


def test_the_docs_list_each_kinds_scenarios_as_the_kind_declares_them():
    """The scenario table of docs/verify.md: a column for every kind (kinds that share a column are named together),
    "runs" (or "runs (...)") exactly where the kind runs the scenario, a row for every scenario."""
    from codegen.verify.plan import SCENARIOS

    text = (REPO / "docs" / "verify.md").read_text(encoding="utf-8")
    header = next(line for line in text.splitlines() if line.startswith("| scenario |"))
    table = text.split(header, 1)[1].split("\n\n", 1)[0]
    columns = {}
    for column, names in enumerate(header.strip("|").split("|")[1:], start=1):
        for name in names.split(","):
            columns[name.strip()] = column
    assert set(columns) == set(installed_kinds()), f"docs/verify.md's scenario table has columns {sorted(columns)}"
    rows = [line.strip("|").split("|") for line in table.strip().splitlines()[1:]]
    assert len(rows) == len(SCENARIOS), "a row for every scenario, in codegen.verify.plan.SCENARIOS's order"
    for row, scenario in zip(rows, SCENARIOS, strict=True):
        for kind, column in columns.items():
            runs = row[column].strip().startswith("runs")
            assert runs == (installed_kinds()[kind].verify.scenarios[scenario] == ""), (scenario, kind, row[column])
