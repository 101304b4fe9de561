"""The moving bodies: the arm's capsules from the catalogue, the tool and the carried part, and which pairs of
them are checked against each other."""

from __future__ import annotations

from dataclasses import dataclass

from codegen.robot.arms import Arm
from codegen.world.solids import Box, Capsule, Cylinder

FLANGE = 6  # the link frame the tool and the part are fixed in
CARRIED = 7  # the tool's and part's place in the chain for the neighbour rule (one beyond the flange)
NEIGHBOURS = 3  # bodies whose chain places differ by less than this are not checked against each other


@dataclass(frozen=True, eq=False)
class Body:
    """A moving shape: its name, the link frame it is fixed in, its place in the chain (the link frame for the arm's
    links, CARRIED for the tool and part) and its shape (the shape's pose: body2frame)."""

    name: str
    frame: int
    chain: int
    shape: Box | Cylinder | Capsule


def arm_bodies(arm: Arm, tool: Box | Cylinder | Capsule | None = None, part: Box | None = None) -> tuple[Body, ...]:
    """The arm's capsules (the catalogue's `links`), then the tool and the carried part (shapes in the flange frame)."""
    if not arm.links:
        raise ValueError(f"arm {arm.model!r}: the catalogue gives it no link shapes (key `links`)")
    out = [Body(link.name, link.frame, link.frame, Capsule(link.radius, link.a, link.b)) for link in arm.links]
    if tool is not None:
        out.append(Body("tool", FLANGE, CARRIED, tool))
    if part is not None:
        out.append(Body("part", FLANGE, CARRIED, part))
    return tuple(out)


def self_pairs(arm: Arm, bodies: tuple[Body, ...]) -> tuple[tuple[int, int], ...]:
    """Index pairs of bodies checked against each other: places in the chain at least NEIGHBOURS apart (a joint's
    two housings and the housings one joint further meet by construction; their joint limits keep them apart, as
    collision tools skip consecutive links), less the arm's `self_allowed` link pairs; never the tool against the
    part (the tool holds it)."""
    allowed = set(arm.self_allowed)
    out = []
    for i, one in enumerate(bodies):
        for j in range(i + 1, len(bodies)):
            other = bodies[j]
            if abs(one.chain - other.chain) < NEIGHBOURS:
                continue
            frames = (min(one.frame, other.frame), max(one.frame, other.frame))
            if CARRIED not in (one.chain, other.chain) and frames in allowed:
                continue
            out.append((i, j))
    return tuple(out)
