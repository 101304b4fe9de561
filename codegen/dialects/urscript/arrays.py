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
from codegen.dialects.urscript.values import int32

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
    return int32(OPERATORS[symbol](a, b), f"the {symbol} of an element", where)


def operation(symbol: str):
    """(a, b, where) -> a <symbol> b where one of them is an array (the compiled code's slow path)."""

    def op(a, b, where):
        return _apply(symbol, a, b, where)

    return op


# --- which expressions are never arrays (their arithmetic needs no test for one) -------------------------
# Built-ins that return an array (a list of numbers); every other built-in returns a number, a pose, a string,
# a boolean, a struct or nothing.
LIST_BUILTINS = frozenset(
    {
        "get_actual_joint_positions",
        "get_target_joint_positions",
        "get_inverse_kin",
        "rpy2rotvec",
        "rotvec2rpy",
        "normalize",
        "pose_to_list",
        "get_tcp_force",
    }
)
NEVER_LIST_RULES = frozenset({"number", "string", "true", "false", "compare", "and_", "or_", "not_", "xor"})
ARITHMETIC_RULES = frozenset({"add", "sub", "mul", "div", "mod", "neg"})


class NeverLists:
    """The program's variables that only ever hold values that are not arrays (every assignment to them, in
    any function, is such a value; a parameter or a variable assigned element by element may be an array),
    found once when the program is compiled; `never(node)` says whether an expression is never an array."""

    def __init__(self, tree, builtins: dict, functions: set[str]) -> None:
        self.builtins = frozenset(name for name in builtins if name not in functions and name not in LIST_BUILTINS)
        values: dict[str, list] = {}
        excluded: set[str] = set()
        for node in tree.iter_subtrees():
            if node.data == "assign":
                target = node.children[0]
                if hasattr(target, "data") and target.data == "var":
                    values.setdefault(str(target.children[0]), []).append(node.children[1])
                else:  # x[i] = v, x.f = v: x holds an array or a record
                    while hasattr(target, "data") and target.data in ("index", "field"):
                        target = target.children[0]
                    if hasattr(target, "data") and target.data == "var":
                        excluded.add(str(target.children[0]))
            elif node.data in ("global_stmt", "local_stmt") and node.children[1] is not None:
                values.setdefault(str(node.children[0]), []).append(node.children[1])
            elif node.data == "param":
                excluded.add(str(node.children[0]))
        self.names = set(values) - excluded
        changed = True
        while changed:
            changed = False
            for name in list(self.names):
                if not all(self.never(value) for value in values[name]):
                    self.names.discard(name)
                    changed = True

    def never(self, node) -> bool:
        kind = getattr(node, "data", None)
        if kind is None:
            return False
        if kind in NEVER_LIST_RULES or kind in ("pose_lit", "run_thread"):
            return True
        if kind in ARITHMETIC_RULES:
            return all(self.never(c) for c in node.children if hasattr(c, "data"))
        if kind == "var":
            return str(node.children[0]) in self.names
        if kind == "call":
            callee = node.children[0]
            return getattr(callee, "data", None) == "var" and str(callee.children[0]) in self.builtins
        return False
