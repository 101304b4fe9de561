"""Jinja's internals that codegen/jinjadoor.py relies on are still there, and still mean the same."""

from __future__ import annotations

import tomllib
from pathlib import Path

import jinja2
import pytest
from jinja2.compiler import CodeGenerator
from packaging.requirements import Requirement
from packaging.version import Version

from codegen.jinjadoor import marking_environment

ROOT = Path(__file__).resolve().parent.parent


class Marked(str):
    __slots__ = ()


class Refused(Exception):
    pass


def _checked(value, where: str) -> Marked:
    if isinstance(value, Marked):
        return value
    raise Refused(f"{where}: {value!r}")


def _environment(**templates) -> jinja2.Environment:
    @jinja2.pass_context
    def finalize(context, value):
        return _checked(value, context.name)

    return marking_environment(Marked, _checked)(
        loader=jinja2.DictLoader(templates), undefined=jinja2.StrictUndefined, finalize=finalize, autoescape=False
    )


def test_installed_jinja_is_within_the_pinned_minor():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    requirement = next(r for r in map(Requirement, project["dependencies"]) if r.name == "jinja2")
    assert Version(jinja2.__version__) in requirement.specifier, (jinja2.__version__, str(requirement))
    upper = next(s for s in requirement.specifier if s.operator == "<")
    assert len(Version(upper.version).release) >= 2, "Jinja's code generator changes between minor versions"


def test_the_code_generator_has_the_hooks_overridden():
    for name in ("visit_Const", "visit_Concat", "visit", "write"):
        assert callable(getattr(CodeGenerator, name)), name
    assert jinja2.Environment.code_generator_class is CodeGenerator
    assert jinja2.Environment.concat("ab") == "ab"  # "".join, called on each output's parts


def test_a_templates_own_text_and_output_are_marked():
    env = _environment(page="{% macro m(x) %}<{{ x }}>{% endmacro %}{{ 'lit' }}|{{ m(v) }}|{{ 'a' ~ v }}")
    out = env.get_template("page").render(v=Marked("V"))
    assert out == "lit|<V>|aV"
    assert type(out) is Marked  # joined by Environment.concat


def test_an_unmarked_value_is_refused_wherever_printed():
    env = _environment(plain="{{ v }}", tilde="{{ 'a' ~ v }}", macro="{% macro m(x) %}{{ x }}{% endmacro %}{{ m(v) }}")
    for name in ("plain", "tilde", "macro"):
        with pytest.raises(Refused, match=rf"{name}: 'cell'"):
            env.get_template(name).render(v="cell")


def test_a_tilde_names_its_template():
    """visit_Concat writes the template's name (CodeGenerator.name) into the compiled source."""
    env = _environment(named="{{ v ~ 'x' }}")
    with pytest.raises(Refused, match=r"^named: 1$"):
        env.get_template("named").render(v=1)
