"""The laser kind's controller facts: its table [program.laser] of a target (targets/<t>.toml)."""

from __future__ import annotations

from codegen.protocol import get_kind


def facts(target) -> dict:
    """[program.laser] of a target, checked against the kind's keys ({}: the target has none)."""

    return get_kind("laser").facts(target)
