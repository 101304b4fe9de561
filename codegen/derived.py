"""The cached derivation (derived.json): identities and closed forms, readable without sympy."""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path

CACHE_PATH = Path(__file__).with_name("derived.json")


@cache
def load() -> dict:
    return json.loads(CACHE_PATH.read_text(encoding="utf-8"))


def printed(dialect: str, block: str) -> dict:
    """{"temps": [[name, code], ...], "outputs": {name: code}} for one dialect and block."""
    return load()["printed"][dialect][block]
