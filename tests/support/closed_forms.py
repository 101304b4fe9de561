"""The derivation's printed closed forms evaluated in float64 (their Python printing in derived.json)."""

from __future__ import annotations

import math

from codegen import derived


def evaluate(block: str, inputs: dict[str, float]) -> dict[str, float]:
    """A cached block's outputs for the given inputs, in float64."""
    scope: dict[str, float] = dict(inputs)
    code = derived.printed("python", block)
    for name, expr in code["temps"]:
        scope[name] = eval(expr, {"math": math}, scope)  # package data written by codegen/derivation.py
    return {name: eval(expr, {"math": math}, scope) for name, expr in code["outputs"].items()}
