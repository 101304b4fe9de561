"""The libraries codegen is written against are bounded in pyproject.toml, and the installed ones are within bounds."""

from __future__ import annotations

import tomllib
from importlib.metadata import version
from pathlib import Path

import pytest
from packaging.requirements import Requirement
from packaging.version import Version

ROOT = Path(__file__).resolve().parent.parent
DEPENDENCIES = [
    Requirement(text) for text in tomllib.loads((ROOT / "pyproject.toml").read_text("utf-8"))["project"]["dependencies"]
]


@pytest.mark.parametrize("requirement", DEPENDENCIES, ids=lambda r: r.name)
def test_a_dependency_has_an_upper_bound_and_the_installed_version_is_within_it(requirement):
    """A new major (for lark and Jinja, whose internals the doors use: a new minor) may change what codegen calls:
    it comes in by raising the bound after the tests pass with it, not by itself."""
    assert any(s.operator in ("<", "<=", "==", "~=") for s in requirement.specifier), f"{requirement}: no upper bound"
    installed = Version(version(requirement.name))
    assert installed in requirement.specifier, f"{requirement.name} {installed} is outside {requirement.specifier}"


def test_the_libraries_used_directly_are_declared():
    """markupsafe (the view's page), lark, Jinja, sympy, numpy and the clearance engine are named, not pulled in."""
    assert {"markupsafe", "lark", "jinja2", "sympy", "numpy", "coal"} <= {r.name.lower() for r in DEPENDENCIES}
