"""templates/ and targets/ sit at the top of the repository and still ship in the wheel (both install modes)."""

from __future__ import annotations

import shutil
import subprocess
import sys
import venv
import zipfile
from pathlib import Path

import pytest

from codegen.controllers import target_names

REPO = Path(__file__).resolve().parents[1]
PROBE = (
    "from codegen import data_dir; from codegen.controllers import target_names; "
    "print(data_dir('templates')); print(','.join(target_names()))"
)


def _pip(*args: str, python: str = sys.executable) -> None:
    proc = subprocess.run([python, "-m", "pip", "-q", *args], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    source = tmp_path_factory.mktemp("source") / "codegen"  # a clean copy: no stale build/ of the checkout
    source.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(REPO / name, source / name)
    for name in ("codegen", "templates", "targets"):
        shutil.copytree(REPO / name, source / name, ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
    _pip("wheel", "--no-deps", "-w", str(out), str(source))
    (path,) = out.glob("codegen-*.whl")
    return path


@pytest.mark.slow  # builds a wheel (pip wheel of a copy of the checkout)
def test_the_wheel_carries_templates_targets_grammars_and_the_derivation(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    expected = {f"codegen/targets/{p.name}" for p in (REPO / "targets").glob("*.toml")}
    expected |= {f"codegen/templates/{p.relative_to(REPO / 'templates')}" for p in (REPO / "templates").rglob("*.j2")}
    expected |= {f"codegen/{p.relative_to(REPO / 'codegen')}" for p in (REPO / "codegen").rglob("*.lark")}
    expected |= {"codegen/derived.json"}
    expected |= {f"codegen/kinds/{p.parent.name}/kind.py" for p in (REPO / "codegen" / "kinds").glob("*/kind.py")}
    expected |= {f"codegen/{p.relative_to(REPO / 'codegen')}" for p in (REPO / "codegen" / "examples").rglob("*.toml")}
    expected |= {f"codegen/{p.relative_to(REPO / 'codegen')}" for p in (REPO / "codegen" / "examples").rglob("*.csv")}
    expected |= {f"codegen/view/static/{p.name}" for p in (REPO / "codegen" / "view" / "static").iterdir()}
    plant = REPO / "codegen" / "examples" / "plant" / "generated"  # the example plant's programs, for `codegen diff`
    expected |= {f"codegen/{p.relative_to(REPO / 'codegen')}" for p in plant.glob("*/*/*")}
    assert expected <= names, sorted(expected - names)


def _fresh_python(tmp_path: Path) -> str:
    venv.create(tmp_path / "venv", with_pip=True)
    return str(tmp_path / "venv" / "bin" / "python")


def _probe(python: str, cwd: Path) -> list[str]:
    proc = subprocess.run([python, "-c", PROBE], capture_output=True, text=True, cwd=cwd)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.split()


@pytest.mark.slow
def test_installed_wheel_finds_its_own_files_from_any_directory(wheel, tmp_path):
    python = _fresh_python(tmp_path)
    _pip("install", "--no-deps", str(wheel), python=python)
    templates, names = _probe(python, tmp_path)
    assert Path(templates).is_relative_to(tmp_path / "venv") and (Path(templates) / "ur" / "kinds").is_dir()
    assert names == ",".join(target_names())


@pytest.mark.slow
def test_editable_install_reads_the_checkout(tmp_path):
    """An editable install reads templates/ of the checkout, so a template edit needs no reinstall."""
    python = _fresh_python(tmp_path)
    _pip("install", "--no-deps", "-e", str(REPO), python=python)
    templates, names = _probe(python, tmp_path)
    assert Path(templates) == REPO / "templates"
    assert names == ",".join(target_names())
