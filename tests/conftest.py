"""Shared fixtures: the demo cell, a helper that writes cell files, verify without the kinds' bulk runs, and validators
of the report formats (the schemas in tests/reports/schemas/, its README.md says where each comes from)."""

from __future__ import annotations

import json
import re
from functools import cache
from pathlib import Path

import pytest

from codegen.model.cell import DEMO_CELL, load_cell

SCHEMAS = Path(__file__).resolve().parent / "reports" / "schemas"

# Tests that share an expensive object built once per process, each group run on one xdist worker: the derivation's
# proofs (the kinds cache them per process; the CLI's derive --check proves the same ones), the view pages of every
# bundled cell (a module fixture) with the browser that reads them, and source 004's cell unstacking (a session
# fixture of tests/kinds/conftest.py: its reach and clearance proofs). By node id prefix, a test with its parameters:
# pytest 9 keeps a node's id where xdist 3.8's loadgroup no longer rewrites it, so xdist_group marks would not reach
# the scheduler.
GROUPS = {
    "tests/test_derivation.py": "derivation",
    "tests/test_cli.py::test_derive_json": "derivation",
    "tests/view/test_view_page.py": "view_pages",
    "tests/kinds/test_pallet_programs.py::test_an_unstacked_box_dropped_on_the_way_to_q_is_not_counted_as_taken": (
        "unstacking"
    ),
    "tests/kinds/test_pallet_exchange.py::test_an_unstacking_program_waits_for_the_empty_pallets_swap": "unstacking",
    "tests/kinds/test_pallet_exchange.py::test_an_unstacking_program_empty_at_the_start_waits_above_q": "unstacking",
}
ROOT = Path(__file__).resolve().parent.parent
SHARED_FIXTURE = re.compile(r"""scope=["'](module|class)["']""")  # a fixture the module's tests share


@cache
def _shares_a_fixture(module: str) -> bool:
    path = ROOT / module
    return path.suffix == ".py" and path.is_file() and bool(SHARED_FIXTURE.search(path.read_text(encoding="utf-8")))


@pytest.hookimpl(optionalhook=True)  # `-p no:xdist` runs without the hook
def pytest_xdist_make_scheduler(config, log):
    """--dist loadgroup with GROUPS, and each module that defines a module or class fixture one unit of work (its
    fixture and the per-cell caches of the cells it holds built once); every other test alone, so the workers stay
    evenly busy to the end (xdist sends the largest units first)."""
    if config.getoption("dist") != "loadgroup":
        return None
    from xdist.scheduler import LoadGroupScheduling

    class Grouped(LoadGroupScheduling):
        def _split_scope(self, nodeid: str) -> str:
            for prefix, group in GROUPS.items():
                if nodeid == prefix or nodeid.startswith((prefix + "::", prefix + "[")):  # a test or its params
                    return group
            module = nodeid.split("::", 1)[0]
            return module if _shares_a_fixture(module) else super()._split_scope(nodeid)

    return Grouped(config, log)


def pytest_configure(config):
    """Each bundled cell file (a file under the repository, its bytes and tables as read) becomes one Cell per process,
    whoever loads it (a test, a fixture, the CLI): cells are frozen, so the per-cell work one test does (plans, reach
    proofs) serves the next. Files elsewhere (tmp_path), tables of no such file, other kinds than the installed ones
    and files that fail to load go through the loader every time."""
    from codegen.model import cell as cell_module

    real = cell_module.cell_from_dict
    loaded: dict[tuple[str, str, str], object] = {}

    def cell_from_dict(data, source="<cell>", sha256="", kinds=None):
        path = Path(source).resolve()
        if kinds is not None or not sha256 or not path.is_relative_to(ROOT) or not path.is_file():
            return real(data, source, sha256, kinds)
        key = (source, sha256, json.dumps(data, sort_keys=True, default=repr))  # the tables too: a caller may edit
        if key not in loaded:
            loaded[key] = real(data, source, sha256, kinds)
        return loaded[key]

    config.add_cleanup(lambda: setattr(cell_module, "cell_from_dict", real))
    cell_module.cell_from_dict = cell_from_dict


@pytest.fixture(scope="session")
def demo_cell():
    return load_cell(DEMO_CELL)


@pytest.fixture
def write_cell(tmp_path: Path):
    def write(text: str, name: str = "cell.toml") -> Path:
        path = tmp_path / name
        path.write_text(text, encoding="utf-8")
        return path

    return write


@pytest.fixture(scope="session")
def sarif_valid():
    """A function that raises where a SARIF text is not valid SARIF 2.1.0 (OASIS's JSON schema) and returns it."""
    import jsonschema

    schema = json.loads((SCHEMAS / "sarif-schema-2.1.0.json").read_text(encoding="utf-8"))
    validator = jsonschema.Draft4Validator(schema, format_checker=jsonschema.Draft4Validator.FORMAT_CHECKER)

    def valid(text: str) -> dict:
        log = json.loads(text)
        validator.validate(log)
        return log

    return valid


@pytest.fixture(scope="session")
def junit_valid():
    """A function that raises where a text is not valid against the Jenkins JUnit schema and returns its root."""
    from xml.etree import ElementTree as ET

    import xmlschema

    schema = xmlschema.XMLSchema(str(SCHEMAS / "junit-10.xsd"))

    def valid(text: str):
        schema.validate(text)
        return ET.fromstring(text)

    return valid


@pytest.fixture
def no_sweeps(monkeypatch):
    """verify's engine without the kinds' bulk runs (every station id that is not a station, shown to stop: a few
    thousand runs, which the slow tests run on the same programs), for a command-line test that checks something
    else."""
    from dataclasses import replace

    from codegen.verify import engine

    real = engine.verify_cell

    def verify_cell(cell, files=(), targets=(), options=None):
        return real(cell, files, targets, replace(options or engine.Options(), sweeps=False))

    monkeypatch.setattr(engine, "verify_cell", verify_cell)
