"""The cell's objects in the page: each kind's (ProgramKind.scene), in the registry's order."""

from __future__ import annotations

from codegen.protocol import kinds


def cell_objects(cell) -> list[dict]:
    return [o for kind in kinds().values() for o in kind.scene(cell)]
