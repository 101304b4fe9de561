"""Code printers: one table per language, fixed-decimal literals without -0."""

import pytest
import sympy as sp

from codegen.dialects import printers
from codegen.dialects.printing import format_literal

x, y = sp.symbols("x y")


def test_literals_have_fixed_decimals_and_no_negative_zero():
    assert format_literal(-0.0, 3) == "0.000"
    assert format_literal(-0.0000001, 4) == "0.0000"
    assert format_literal(-1.5, 2) == "-1.50"
    assert format_literal(1e-7, 9) == "0.000000100"


@pytest.mark.parametrize(
    ("dialect", "expected"),
    [
        ("urscript", "x*y*y - 0.500000000*sin(y) + cos(x)"),
        ("krl", "x*y*y - 0.500000*SIN(y) + COS(x)"),
        ("rapid", "x*y*y - 0.500000*Sin(y) + Cos(x)"),
        ("dtrans", "x*y*y - 0.500000*sin(y) + cos(x)"),
    ],
)
def test_each_language_prints_its_function_names(dialect, expected):
    expr = sp.cos(x) - sp.Float(0.5) * sp.sin(y) + x * y**2
    assert printers()[dialect].doprint(expr) == expected


def test_unprintable_power_is_refused():
    with pytest.raises(Exception, match="no controller form"):
        printers()["krl"].doprint(x**3)
