"""The derivation's closed forms evaluated in float64: derived.json's blocks, as sympy's str printer wrote them."""

from __future__ import annotations

import math

from codegen import derived

# the names sympy's str printer gives the functions a block may hold, each as float64 math
FUNCTIONS = {name: getattr(math, name) for name in ("sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sqrt")}
FUNCTIONS |= {"Abs": abs, "pi": math.pi}


def evaluate(block: str, inputs: dict[str, float]) -> dict[str, float]:
    """A cached block's outputs for the given inputs, in float64 (a name outside FUNCTIONS and inputs: NameError)."""
    scope: dict[str, float] = dict(inputs)
    code = derived.load()["blocks"][block]
    for name, expr in code["temps"]:
        scope[name] = eval(expr, {"__builtins__": {}, **FUNCTIONS}, scope)  # package data written by derivation.py
    return {name: eval(expr, {"__builtins__": {}, **FUNCTIONS}, scope) for name, expr in code["outputs"].items()}
