"""The pick program's motion plan: each part's segments (joint or straight, travel or work speed, exact stop or
blended, the payload in force) per tracking mode, the way home at the start, laid over a run by its gripper's
outputs (the grip and the release anchor each picked part)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from codegen.kinds.conveyor.kind import KIND
from codegen.kinds.conveyor.section import conveyor_of
from codegen.verify.plan import TOOL_LOAD, PlannedMove, PlannedOutput
from codegen.world import loads


@dataclass(frozen=True)
class Segment:
    key: str  # the template's name of the move (its blend: targets/<t>.toml [program.conveyor] blends)
    name: str
    kind: str  # "joint" or "linear"
    speed: str  # "travel" or "work" ([cell.motion]); "home": the controller's own (its facts' speed and zone)
    held: bool = False  # the part's payload in force (from the grip confirmed to the release)


# Each picked part, as the program moves for it; the grip comes after `grip`, the release after `release` moves.
PICK = {
    "native": (  # wait across from the part at the window's start clear of the tallest part, then follow the belt
        Segment("wait", "wait above the window's start", "joint", "travel"),
        Segment("above_part", "above the part", "linear", "travel"),
        Segment("on_part", "on the part", "linear", "work"),
        Segment("lift", "lift", "linear", "work", True),
        Segment("above_place", "above the place", "joint", "travel", True),
        Segment("place", "place", "linear", "work", True),
        Segment("lift_place", "lift from the place", "linear", "work"),
    ),
    "intercept": (  # wait above the meeting point clear of the tallest part, come down as the part arrives
        Segment("wait", "above the intercept", "joint", "travel"),
        Segment("above_part", "above the part", "linear", "work"),
        Segment("on_part", "on the part", "linear", "work"),
        Segment("lift", "lift", "linear", "work", True),
        Segment("above_place", "above the place", "joint", "travel", True),
        Segment("place", "place", "linear", "work", True),
        Segment("lift_place", "lift from the place", "linear", "work"),
    ),
}
# the moves after which every pick program waits (for the part, the place's interlock, the queue) or sets an output (the
# grip, the release) before it commands the next: none of them blends (a blend into a wait does not stop the arm there)
WAITS_AFTER = {
    "native": frozenset({"wait", "on_part", "above_place", "place", "lift_place"}),
    "intercept": frozenset({"wait", "above_part", "on_part", "above_place", "place", "lift_place"}),
}
GRIP = {"native": 3, "intercept": 3}  # moves of a part before its grip
RELEASE = {"native": 6, "intercept": 6}  # moves of a part before its release
# a part given up after the arm moved for it: the moves made for it (the waiting move; an intercept's move down to the
# part's approach height and back up to the clear height (the lift's segment, nothing held); the whole descent and its
# lift to the clear height:
# a part that reached the window's end while the arm came down, or a grip not confirmed in time; where the program
# leaves the belt in a fixed work object before it disconnects (ABB native), then the move above the window's start)
GIVEN_UP = {"native": ((0,), (0, 1, 2, 3), (0, 1, 2, 3, 0)), "intercept": ((0,), (0, 1, 3), (0, 1, 2, 3))}
# The way home at the start from wherever a stop left the arm: a joint move to where it stands (the controller's
# first motion), back out along the tool's axis, a safe pose above the belt, home; a part held is then put down
# at the place before the first pick.
AWAY = (
    Segment("here", "where the arm stands", "joint", "home"),
    Segment("back_out", "back out along the tool's axis", "linear", "work"),
    Segment("safe", "the safe pose above the belt", "joint", "travel"),
)
HOME = Segment("home", "home", "joint", "home")
PUT_DOWN = (  # a part held at the start
    Segment("above_place", "above the place", "joint", "travel", True),
    Segment("place", "place", "linear", "work", True),
    Segment("lift_place", "lift from the place", "linear", "work"),
)


def blends(cell, target, mode: str) -> dict[str, bool]:
    """Which moves of the pick blend into the next ([cell.motion] zone_mm; the target's program blends the
    segments its facts list: the travel moves a move follows at once), by segment key."""
    listed = set(KIND.facts(target).get("blends", {}).get(mode, ()))
    zone = cell.motion.zone_mm > 0
    keys = {s.key for s in PICK[mode]}
    return {key: zone and key in listed for key in sorted(keys)}


def part_load(cell) -> loads.Load:
    """The part in the gripper in the tool frame (a payload's frame): a solid box of part_size_mm along the tool
    frame's axes centred at part_cog_mm, or a point mass there where the cell gives no size."""
    pick = conveyor_of(cell).pick
    centre2tcp = np.eye(4)
    centre2tcp[:3, 3] = pick.part_cog_mm
    return loads.held_box(pick.part_mass_kg, pick.part_size_mm, centre2tcp, np.eye(4))


def carried_load(cell) -> loads.Load:
    """The load while the gripper holds a part: the tool's and the part's as one, in the flange frame (mass, common
    centre of gravity, the tensor about it with the parallel-axis terms)."""
    robot = cell.robot
    tool = loads.of_tool(robot.tool, robot.tool_shaped)
    return loads.combined(tool, part_load(cell).moved(robot.tool.tcp2flange))


def carried(cell) -> tuple[float, ...]:
    """The planned load while the gripper holds a part, as verify compares it (codegen.world.loads.Load.flat)."""
    return carried_load(cell).flat()


def planned(segment: Segment, cell, target, mode: str | None = None, pose=None, joints=None) -> PlannedMove:
    speed = {"travel": cell.motion.speed_mm_s, "work": cell.motion.work_speed_mm_s}.get(segment.speed)
    percent = cell.motion.joint_speed_percent if segment.kind == "joint" else None
    blend = mode is not None and blends(cell, target, mode).get(segment.key, False)
    payload = carried(cell) if segment.held and cell.robot is not None and cell.robot.tool_given else TOOL_LOAD
    zone = cell.motion.zone_mm if blend else 0.0
    return PlannedMove(
        name=segment.name,
        kind=segment.kind,
        tcp2base=pose,
        exact=not blend,
        speed_mm_s=speed,
        zone_mm=zone,
        joint_percent=percent,
        joints=joints,
        payload=payload,
    )


def lay_over(cell, target, mode: str, first: int, moves: list, closes: list, opens: list) -> list[PlannedMove] | str:
    """The plan of the moves from index `first` on: each picked part's segments where its grip (a close) and its
    release (an open) put them; the moves between as a part given up (GIVEN_UP). A run whose moves fit no such
    plan is named where it leaves it (the returned text)."""
    segments, grip, release = PICK[mode], GRIP[mode], RELEASE[mode]
    out: list[PlannedMove] = []
    i = first
    for close, open_ in zip(closes, opens, strict=False):
        start = close.after_moves - grip
        gap = _given_up(cell, target, mode, moves[i:start], i)
        if isinstance(gap, str):
            return gap
        out += gap
        if start < i or open_.after_moves != start + release:
            return f"the grip after move {close.after_moves} and the release after move {open_.after_moves} fit no pick"
        out += [planned(s, cell, target, mode) for s in segments]
        i = start + len(segments)
    tail = _given_up(cell, target, mode, moves[i:], i)
    if isinstance(tail, str):
        return tail
    return out + tail


def _given_up(cell, target, mode: str, moves: list, offset: int) -> list[PlannedMove] | str:
    """Moves for parts given up: each a run of the waiting move and, while tracking, the descent and lift (the lift
    of a part given up holds nothing)."""
    segments, out, i = PICK[mode], [], 0
    patterns = sorted(GIVEN_UP[mode], key=len, reverse=True)
    while i < len(moves):
        for pattern in patterns:
            kinds = [segments[k].kind for k in pattern]
            if [m.kind for m in moves[i : i + len(pattern)]] == kinds and _starts_part(moves, i, len(pattern)):
                for k in pattern:
                    segment = segments[k]
                    unheld = Segment(segment.key, segment.name, segment.kind, segment.speed)
                    # the lift of a part left on the belt stops before the tracking ends
                    out.append(planned(unheld, cell, target, mode if segment.key != "lift" else None))
                i += len(pattern)
                break
        else:
            return f"move {offset + i + 1} ({moves[i].kind}, line {moves[i].line}) is in no part's plan"
    return out


def _starts_part(moves: list, i: int, length: int) -> bool:
    """A given-up part's moves are followed by the next part's waiting move or the end."""
    after = i + length
    return after >= len(moves) or moves[after].kind == "joint"


def outputs(
    cell, name: str, closes: list, opens: list, release_at: int | None, held_at: int | None = None
) -> tuple[PlannedOutput, ...]:
    """The gripper's outputs a pick run sets: with a part held at the start, the grip asserted again after move
    held_at (at home, before the way to the place); released once at the start (after move release_at: at home with
    nothing held, at the place with a part held; None: not at all), then a grip and a release per picked part
    at the moves the plan puts them."""
    out = [] if held_at is None else [PlannedOutput(name, cell.io.value, held_at, "asserted again, a part held")]
    if release_at is not None:
        out.append(PlannedOutput(name, not cell.io.value, release_at, "released at the start"))
    for close, open_ in zip(closes, opens, strict=False):
        out.append(PlannedOutput(name, cell.io.value, close.after_moves, "on the part"))
        out.append(PlannedOutput(name, not cell.io.value, open_.after_moves, "at the place"))
    return tuple(out)
