"""The cached derivation (derived.json): identities and closed forms, readable without sympy."""

from __future__ import annotations

import json
import math
from functools import cache
from pathlib import Path

CACHE_PATH = Path(__file__).with_name("derived.json")


@cache
def load() -> dict:
    return json.loads(CACHE_PATH.read_text(encoding="utf-8"))


def printed(dialect: str, block: str) -> dict:
    """{"temps": [[name, code], ...], "outputs": {name: code}} for one dialect and block."""
    return load()["printed"][dialect][block]


def evaluate(block: str, inputs: dict[str, float]) -> dict[str, float]:
    """Evaluate a cached block ("frame" or "point") in float64 from its Python printing."""
    scope: dict[str, float] = dict(inputs)
    code = printed("python", block)
    for name, expr in code["temps"]:
        scope[name] = eval(expr, {"math": math}, scope)  # package data written by derivation.py
    return {name: eval(expr, {"math": math}, scope) for name, expr in code["outputs"].items()}
