"""The pick program's motion plan: each part's segments (joint or straight, travel or work speed, exact stops) per
tracking mode, laid over a run by its gripper's outputs (the grip and the release anchor each picked part)."""

from __future__ import annotations

from dataclasses import dataclass

from codegen.verify.plan import PlannedMove, PlannedOutput


@dataclass(frozen=True)
class Segment:
    name: str
    kind: str  # "joint" or "linear"
    speed: str  # "travel" or "work" ([cell.motion]); a joint move: the controller's joint speed
    exact: bool = True  # every move of the pick programs stops at its pose (no blending)


# Each picked part, as the program moves for it; the grip comes after `grip`, the release after `release` moves.
PICK = {
    "native": (  # wait across from the part at the window's start, then follow the belt (track_conveyor_linear)
        Segment("wait above the window's start", "joint", "travel"),
        Segment("above the part", "linear", "travel"),
        Segment("on the part", "linear", "work"),
        Segment("lift", "linear", "work"),
        Segment("above the place", "joint", "travel"),
        Segment("place", "linear", "work"),
        Segment("lift from the place", "linear", "work"),
    ),
    "intercept": (  # wait above the meeting point, come down as the part arrives
        Segment("above the intercept", "joint", "travel"),
        Segment("on the part", "linear", "work"),
        Segment("lift", "linear", "work"),
        Segment("above the place", "joint", "travel"),
        Segment("place", "linear", "work"),
        Segment("lift from the place", "linear", "work"),
    ),
}
GRIP = {"native": 3, "intercept": 2}  # moves of a part before its grip
RELEASE = {"native": 6, "intercept": 5}  # moves of a part before its release
# a part given up after the arm moved for it: the moves made for it (the waiting move; while tracking, the
# whole descent and its lift)
GIVEN_UP = {"native": ((0,), (0, 1, 2, 3)), "intercept": ((0,),)}


def planned(segment: Segment, cell) -> PlannedMove:
    speed = cell.motion.speed_mm_s if segment.speed == "travel" else cell.motion.work_speed_mm_s
    percent = cell.motion.joint_speed_percent if segment.kind == "joint" else None
    return PlannedMove(segment.name, segment.kind, None, segment.exact, speed, 0.0, percent)


def lay_over(cell, mode: str, first: int, moves: list, closes: list, opens: list) -> list[PlannedMove] | str:
    """The plan of the moves from index `first` on: each picked part's segments where its grip (a close) and its
    release (an open) put them; the moves between as a part given up (GIVEN_UP). A run whose moves fit no such
    plan is named where it leaves it (the returned text)."""
    segments, grip, release = PICK[mode], GRIP[mode], RELEASE[mode]
    out: list[PlannedMove] = []
    i = first
    for close, open_ in zip(closes, opens, strict=False):
        start = close.after_moves - grip
        gap = _given_up(cell, mode, moves[i:start], i)
        if isinstance(gap, str):
            return gap
        out += gap
        if start < i or open_.after_moves != start + release:
            return f"the grip after move {close.after_moves} and the release after move {open_.after_moves} fit no pick"
        out += [planned(s, cell) for s in segments]
        i = start + len(segments)
    tail = _given_up(cell, mode, moves[i:], i)
    if isinstance(tail, str):
        return tail
    return out + tail


def _given_up(cell, mode: str, moves: list, offset: int) -> list[PlannedMove] | str:
    """Moves for parts given up: each a run of the waiting move and, while tracking, the descent and lift."""
    segments, out, i = PICK[mode], [], 0
    patterns = sorted(GIVEN_UP[mode], key=len, reverse=True)
    while i < len(moves):
        for pattern in patterns:
            kinds = [segments[k].kind for k in pattern]
            if [m.kind for m in moves[i : i + len(pattern)]] == kinds and _starts_part(moves, i, len(pattern)):
                out += [planned(segments[k], cell) for k in pattern]
                i += len(pattern)
                break
        else:
            return f"move {offset + i + 1} ({moves[i].kind}, line {moves[i].line}) is in no part's plan"
    return out


def _starts_part(moves: list, i: int, length: int) -> bool:
    """A given-up part's moves are followed by the next part's waiting move or the end."""
    after = i + length
    return after >= len(moves) or moves[after].kind == "joint"


def outputs(cell, name: str, closes: list, opens: list, release_first: bool) -> tuple[PlannedOutput, ...]:
    """The gripper's outputs a pick run sets: released at home (after the home move), then a grip and a release
    per picked part at the moves the plan puts them."""
    out = [PlannedOutput(name, not cell.io.value, 1, "at home, released")] if release_first else []
    for close, open_ in zip(closes, opens, strict=False):
        out.append(PlannedOutput(name, cell.io.value, close.after_moves, "on the part"))
        out.append(PlannedOutput(name, not cell.io.value, open_.after_moves, "at the place"))
    return tuple(out)
