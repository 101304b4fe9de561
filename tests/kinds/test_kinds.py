"""Every program kind on the one base (tests/kinds/kind_base.py), and the registry: what loading a cell imports, a kind
from outside the tree, figures that add up."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from kind_base import KindTests

from codegen.model.cell import example_cells, load_cell
from codegen.protocol import Figures, Kinds, installed_kinds


class TestStation(KindTests):
    kind = "station"


class TestPallet(KindTests):
    kind = "pallet"


class TestConveyor(KindTests):
    kind = "conveyor"


class TestLaser(KindTests):
    kind = "laser"


# --- the registry: the kinds a cell is loaded with, a kind from outside the tree ---------------------------------

REPO = Path(__file__).resolve().parents[2]
TOY = REPO / "tests" / "support" / "toykind"
# what loading a cell must not import: the verify engine, the page, the templates, the simulators, the command line,
# the floors above the kinds (plant, language server, reports, generate), the symbolic math, the parsers and the
# collision library (a kind's plan, writer, verify plan, scene, commands and derivation are made when first asked)
HEAVY = (
    "codegen.verify", "codegen.view", "codegen.render", "codegen.sim", "codegen.plant", "codegen.lsp",
    "codegen.reports", "codegen.cli", "codegen.generate", "click", "sympy", "jinja2", "lark", "coal",
)
IMPORTED = """
import json, sys
from codegen.model.cell import load_cell
load_cell(sys.argv[1])
print(json.dumps(sorted(sys.modules)))
"""


@pytest.mark.parametrize("path", example_cells(), ids=lambda p: p.stem)
def test_loading_a_cell_imports_none_of_the_heavy_modules(path):
    """Each bundled cell loaded in a fresh interpreter: none of the modules of verify, the page, rendering, the
    simulators, click or sympy comes in (the kinds' sections alone are imported)."""
    done = subprocess.run([sys.executable, "-c", IMPORTED, str(path)], capture_output=True, text=True, check=True)
    modules = json.loads(done.stdout)
    heavy = [m for m in modules if any(m == h or m.startswith(h + ".") for h in HEAVY)]
    own = [m for m in modules if m.startswith("codegen")]
    assert not heavy, f"{path.name}: loading imports {heavy[:10]} ({len(own)} codegen modules)"


def _installed_beside(tmp_path: Path) -> dict:
    """An environment in which the toy kind is a distribution of its own in tmp_path (its package copied there) that
    registers the kind in the group codegen.kinds, as `pip install` of a package with that entry point would."""
    site = tmp_path / "site"
    shutil.copytree(TOY, site / "toykind", ignore=shutil.ignore_patterns("__pycache__", "*.toml"))
    info = site / "toykind-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: toykind\nVersion: 0.1\n", encoding="utf-8")
    (info / "entry_points.txt").write_text("[codegen.kinds]\ntoy = toykind.kind:KIND\n", encoding="utf-8")
    return {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), os.environ.get("PYTHONPATH", "")])}


def _codegen(env: dict, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "codegen", *args], capture_output=True, text=True, env=env)


def test_a_kind_from_outside_the_tree_registers_through_its_entry_point(tmp_path):
    """The toy kind (tests/support/toykind: a package, its template, an example cell) installed beside codegen:
    its cell loads, generates its program from its own template, verifies, and its command is codegen's."""
    env = _installed_beside(tmp_path)
    cell = TOY / "example.toml"
    done = _codegen(env, "generate", str(cell), "--out", str(tmp_path / "out"))
    assert done.returncode == 0, done.stderr
    (program,) = (tmp_path / "out").rglob("*.script")
    assert program.relative_to(tmp_path / "out").as_posix() == "toy_cell/ur/toy_toy_cell.script"
    assert program.read_text(encoding="utf-8") == 'def toy_toy_cell():\n  textmsg("hello from outside")\nend\n'
    done = _codegen(env, "verify", str(cell), "--json", "--jobs", "1", "--cases", "1")
    assert done.returncode == 0, done.stdout + done.stderr
    report = json.loads(done.stdout)
    (row,) = report["programs"]
    assert (row["kind"], row["cases"], row["mismatches"], row["greetings"]) == ("toy", 1, 0, 1)
    assert report["toys"] == [row]  # its own list, as the kind lists it (every key of the row)
    done = _codegen(env, "toy-greeting", str(cell))
    assert (done.returncode, done.stdout) == (0, "hello from outside\n"), done.stderr
    assert _codegen(dict(os.environ), "generate", str(cell), "--out", str(tmp_path / "without")).returncode == 2


def test_a_cell_is_read_by_the_kinds_it_is_loaded_with(tmp_path):
    """The kinds given to the loader are the ones that read the cell file and write its programs: without the toy
    kind [toy] is an unknown table; with it the cell holds the toy's section and the toy's program, and only its."""
    from codegen.model.validate import CellError
    from codegen.render import render
    from tests.support.toykind.kind import KIND

    with pytest.raises(CellError, match=r"toy: unknown table"):
        load_cell(TOY / "example.toml")
    kinds = installed_kinds().with_kinds(KIND)
    cell = load_cell(TOY / "example.toml", kinds)
    assert cell.kinds is kinds and list(cell.sections) == ["toy"]
    assert [f.relpath for f in render(cell)] == ["toy_cell/ur/toy_toy_cell.script"]
    assert list(kinds)[-1] == "toy" and isinstance(kinds, Kinds)


def test_figures_add_up_field_by_field():
    """`a + b` of a kind's figures is its chunks together: counts add, lists join, a largest stays the largest."""
    from codegen.kinds.laser.plan import LaserFigures
    from codegen.kinds.pallet.verify import PalletFigures
    from codegen.kinds.station.modes.frame import FrameStats

    assert PalletFigures(2) + PalletFigures(3) == PalletFigures(5)
    assert FrameStats([1], [0.5], [0.1]) + FrameStats([2], [0.2], [0.3]) == FrameStats([1, 2], [0.5, 0.2], [0.1, 0.3])
    most = LaserFigures(0.03, 0.2, 10.0, 0.001) + LaserFigures(0.05, 0.1, 9.0, 0.002)
    assert most == LaserFigures(0.05, 0.2, 10.0, 0.002)
    assert all(issubclass(k.verify.figures, Figures) for k in installed_kinds().values())
