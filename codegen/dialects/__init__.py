"""Registry of controller languages: each folder holds printer.py (and grammar/interpreter)."""

from __future__ import annotations

import importlib

# dialect name -> package under codegen.dialects; targets/<t>.toml names its dialect.
DIALECTS = ("python", "urscript", "krl", "rapid", "dtrans")


def printers() -> dict:
    """One configured sympy code printer per dialect (imports sympy)."""
    out = {}
    for name in DIALECTS:
        module = importlib.import_module(f"codegen.dialects.{name}.printer")
        out[name] = module.Printer()
    return out


# generated file suffix -> dialect whose grammar parses it (the .dat of KRL is parsed as KRL too)
SUFFIX_DIALECT = {".script": "urscript", ".src": "krl", ".dat": "krl", ".mod": "rapid", ".prg": "dtrans"}


def parse_program(name: str, text: str, positions: bool = True):
    """Parse a program with its dialect's grammar; raises with file:line:column on an error."""
    suffix = "." + name.rsplit(".", 1)[-1].lower()
    dialect = SUFFIX_DIALECT.get(suffix)
    if dialect is None:
        raise ValueError(f"{name}: unknown program suffix {suffix}")
    module = importlib.import_module(f"codegen.dialects.{dialect}.interpreter")
    return module.parse(text, name, positions)
