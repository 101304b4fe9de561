"""The conveyor kind's controller facts: its table [program.conveyor] of a target (targets/<t>.toml)."""

from __future__ import annotations

from codegen.protocol import get_kind


def facts(target) -> dict:
    """[program.conveyor] of a target, checked against the kind's keys ({}: the target has none)."""

    return get_kind("conveyor").facts(target)
