"""URScript's arithmetic on arrays: element-wise for arrays of one length, a number applied to every element."""

# The URScript Programming Language, e-Series (SW 5.x), Matrix and Array Expressions: arrays and matrices
# (arrays of arrays) take +, -, * and / element by element, and a number with an array applies to each
# element (as the manual's examples and UR's own admittance-control example use them: `wrench_gain *
# ft_vector`, `ft_vector * 0`). Not confirmed in the manual text at hand: the exact rules for arrays of
# different lengths (refused here) and the matrix product (a matrix times an array or a matrix: refused, not
# modelled, rather than computed element by element).

from __future__ import annotations

import operator

from codegen.dialects.core.values import F32, RunError, describe, f32

OPERATORS = {"+": operator.add, "-": operator.sub, "*": operator.mul, "/": operator.truediv}
NUMBERS = (int, float, F32)


def _is_matrix(value) -> bool:
    return isinstance(value, list) and any(isinstance(v, list) for v in value)


def _apply(symbol: str, a, b, where: str):
    a_list, b_list = isinstance(a, list), isinstance(b, list)
    if a_list and b_list:
        if symbol == "*" and (_is_matrix(a) or _is_matrix(b)):
            raise RunError(f"{where}: a matrix product is not modelled (element-wise * of arrays is)")
        if len(a) != len(b):
            raise RunError(f"{where}: {symbol} of arrays of {len(a)} and {len(b)} elements")
        return [_apply(symbol, x, y, where) for x, y in zip(a, b, strict=True)]
    if a_list:
        return [_apply(symbol, x, b, where) for x in a]
    if b_list:
        return [_apply(symbol, a, y, where) for y in b]
    if isinstance(a, bool) or isinstance(b, bool) or not isinstance(a, NUMBERS) or not isinstance(b, NUMBERS):
        raise RunError(f"{where}: type mismatch ({describe(a)} {symbol} {describe(b)})")
    if symbol == "/":
        if b == 0:
            raise RunError(f"{where}: division by zero")
        return f32(a) / f32(b)
    return OPERATORS[symbol](a, b)


def operation(symbol: str):
    """(a, b, where) -> a <symbol> b where one of them is an array (the compiled code's slow path)."""

    def op(a, b, where):
        return _apply(symbol, a, b, where)

    return op
