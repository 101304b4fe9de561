"""Registry of controller targets: one targets/<name>.toml of vendor facts per controller."""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from functools import cache
from importlib.resources import files
from pathlib import Path

TARGETS_DIR = Path(str(files("codegen.targets")))
TARGET_NAMES = ("ur", "kuka", "abb", "dtrans")


@dataclass(frozen=True)
class Target:
    name: str
    title: str
    dialect: str
    pose_format: str
    files: tuple[str, ...]
    numbers: str
    trig_unit: str
    index_base: int
    identifier_max: int
    identifier_case_sensitive: bool
    string_max: int
    facts: dict  # the whole file, for documentation


@cache
def get_target(name: str) -> Target:
    if name not in TARGET_NAMES:
        raise KeyError(f"unknown target {name!r}; known: {', '.join(TARGET_NAMES)}")
    facts = tomllib.loads((TARGETS_DIR / f"{name}.toml").read_text(encoding="utf-8"))
    return Target(
        name=facts["name"],
        title=facts["title"],
        dialect=facts["dialect"],
        pose_format=facts["pose_format"],
        files=tuple(facts["files"]),
        numbers=facts["numbers"],
        trig_unit=facts["trig_unit"],
        index_base=int(facts["index_base"]),
        identifier_max=int(facts["identifier_max"]),
        identifier_case_sensitive=bool(facts["identifier_case_sensitive"]),
        string_max=int(facts["string_max"]),
        facts=facts,
    )


def all_targets() -> list[Target]:
    return [get_target(name) for name in TARGET_NAMES]
