"""Functions made from a shape's code (codegen/dialects/core/shapes.py) are the code compile() makes of them."""

from __future__ import annotations

from types import CodeType

import pytest

from codegen.dialects.core import shapes
from codegen.dialects.core.shapes import ShapeCache
from codegen.model.cell import load_cell
from codegen.verify.programs import fresh_sources

CELLS = (
    "codegen/examples/agv_machine_tending.toml",
    "codegen/examples/thermometer_bench.toml",
    "codegen/examples/conveyor/belt_pick.toml",
    "codegen/examples/laser/laser_tcp.toml",
    "codegen/examples/pallets/eur_pallet.toml",
)


def _same_code(made: CodeType, direct: CodeType) -> bool:
    """Equal code (bytecode, constants, names, locals, flags, nested code) on the same lines; the
    columns in the line table differ where a placeholder is longer or shorter than its string (they
    place a Python traceback's carets, which codegen never shows)."""
    return (
        [line for *_, line in made.co_lines()] == [line for *_, line in direct.co_lines()]
        and _no_columns(made) == _no_columns(direct)
        and _qualnames(made) == _qualnames(direct)
    )


def _qualnames(code: CodeType) -> list[str]:
    return [code.co_qualname] + [q for c in code.co_consts if isinstance(c, CodeType) for q in _qualnames(c)]


def _no_columns(code: CodeType) -> CodeType:
    consts = tuple(_no_columns(c) if isinstance(c, CodeType) else c for c in code.co_consts)
    return code.replace(co_linetable=b"", co_consts=consts)


def _compiled(name: str, params: str, body: str, namespace: dict):
    scope: dict = {}
    exec(compile(f"def {name}({params}):\n{body}", "<direct>", "exec"), namespace, scope)
    return scope[name]


@pytest.mark.slow
def test_every_function_of_the_bundled_programs_is_what_compile_makes(monkeypatch):
    """Each function every bundled cell's programs compile to, on every target: the code (bytecode,
    constants, names, locals, lines; nested code too), defaults and name equal compile()'s, and
    most are made from a shape already compiled."""
    made = []
    function = ShapeCache.function

    def checked(self, name, params, body, namespace):
        fn = function(self, name, params, body, namespace)
        direct = _compiled(name, params, body, namespace)
        assert _same_code(fn.__code__, direct.__code__), body
        assert (fn.__name__, fn.__defaults__, fn.__kwdefaults__) == (
            direct.__name__,
            direct.__defaults__,
            direct.__kwdefaults__,
        )
        assert fn.__globals__ is namespace
        made.append(self)
        return fn

    monkeypatch.setattr(ShapeCache, "function", checked)
    for path in CELLS:
        cell = load_cell(path)
        for source in fresh_sources(cell, list(cell.targets)):
            source.load()
    caches = set(made)
    shaped = sum(len(cache.shapes) for cache in caches)
    assert len(made) > 1000 and shaped < len(made) / 2  # the reuse this is for (1,000 stations: 37 shapes)


@pytest.mark.parametrize(
    "body, value",
    [
        ("    return 'ab' + 'cd'\n", "abcd"),  # folded by the compiler: not made from the shape
        ("    return 'x' * 3\n", "xxx"),
        ("    return 1 if '' else 2\n", 2),  # an empty string keeps its falseness
        ("    return 1 if 'a' else 2\n", 1),
        ("    return ('it\\'s', \"say \\\"hi\\\"\", '\\n')\n", ("it's", 'say "hi"', "\n")),
        ("    return {'a': _k1, 'b': _k2}['b'] + _w7\n", 5),
        ("    _w3 = _k1\n    return [_w3 + _k2 for _ in 'ab']\n", [3, 3]),
    ],
)
def test_shapes_keep_what_the_source_says(body, value):
    """Folded strings, escapes, a string's truth, names of constants and temporaries, nested code:
    the function gives what the source compiled by itself gives, twice (the second from the shape)."""
    namespace = {"_k1": 1, "_k2": 2, "_w7": 3}
    cache = ShapeCache("<test>")
    first, second = cache.function("f", "fr", body, namespace), cache.function("g", "fr", body, namespace)
    direct = _compiled("f", "fr", body, namespace)
    assert first(None) == second(None) == direct(None) == value
    assert _same_code(first.__code__, direct.__code__)
    assert _same_code(second.__code__, _compiled("g", "fr", body, namespace).__code__)


def test_a_folded_placeholder_is_compiled_as_written():
    cache = ShapeCache("<test>")
    cache.function("f", "fr", "    return 'ab' + 'cd'\n", {})
    assert list(cache.shapes.values()) == [None]
    assert shapes._MARK not in cache.function("f", "fr", "    return 'ab' + 'cd'\n", {})(None)


def test_a_formatted_string_stays_in_the_shape():
    """f'...' is code, not a constant: two functions that format different texts give their own."""
    cache = ShapeCache("<test>")
    first = cache.function("f", "fr", "    return f'{fr}: one'\n", {})
    second = cache.function("f", "fr", "    return f'{fr}: two'\n", {})
    assert (first(1), second(2)) == ("1: one", "2: two")


def test_names_in_a_formatted_string_stay():
    """A routine may be called _k1: its name in a formatted message is text, not a constant's name."""
    cache = ShapeCache("<test>")
    first = cache.function("f", "fr", "    return f'{fr}: _k1 takes 1'\n", {})
    second = cache.function("f", "fr", "    return f'{fr}: _k2 takes 1'\n", {})
    assert (first(1), second(2)) == ("1: _k1 takes 1", "2: _k2 takes 1")
