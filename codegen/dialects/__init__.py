"""Registry of controller languages: each folder holds printer.py (and grammar/interpreter)."""

from __future__ import annotations

import importlib

# dialect name -> package under codegen.dialects; targets/<t>.toml names its dialect.
DIALECTS = ("python",)


def printers() -> dict:
    """One configured sympy code printer per dialect (imports sympy)."""
    out = {}
    for name in DIALECTS:
        module = importlib.import_module(f"codegen.dialects.{name}.printer")
        out[name] = module.Printer()
    return out
