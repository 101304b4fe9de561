"""Clearance proofs kept by the value of what they read: the paths, and the cell's clearance, arms, tool and solids."""

from __future__ import annotations

from codegen.kept import Kept, digest
from codegen.world.cell import clearance_mm, solids, tool_shape
from codegen.world.proof import prove

# the proofs of the kinds that keep none of their own (generate's check of every path a kind plans): an entry is a
# few Least (about 0.5 kB each), so a full store stays well under 1 MB
PROVEN = Kept(128)


def proven(cell, paths: list) -> list:
    """prove(cell, paths) (codegen/world/proof.py), kept by the value of everything it reads: the paths, the cell's
    clearance, each path's arm, the tool (its TCP and its shape) and the cell's solids. A refusal is not kept (it
    raises every time, naming what the cell has now)."""
    key, held = proof_key(cell, paths)
    made = PROVEN.get(key)
    if made is None:
        made = prove(cell, paths)
        PROVEN.put(key, made, held)
    return list(made)


def proof_key(cell, paths: list) -> tuple[bytes, list]:
    """The digest of what prove reads for these paths, and the objects it names by identity."""
    robot = cell.robot
    arms = [robot.arms[path.target] for path in paths]
    return digest(paths, clearance_mm(cell), arms, robot.tool.tcp2flange, solids(cell), tool_shape(cell))
