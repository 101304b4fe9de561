"""The conveyor kind's controller facts: its table [program.conveyor] of a target (targets/<t>.toml)."""

from __future__ import annotations


def facts(target) -> dict:
    """[program.conveyor] of a target, checked against the kind's keys ({}: the target has none)."""
    from codegen.protocol import get_kind  # the registry imports this package: asked when called

    return get_kind("conveyor").facts(target)
