"""generate's clearance proof: every move the kinds plan, swept along its whole path among the cell's solids, at least
the cell's clearance from each; else the move, the body, the solid, the distance and what would fix it."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from codegen import poses
from codegen.decimals import format_literal
from codegen.robot import solve
from codegen.world.bodies import arm_bodies
from codegen.world.cell import FLOOR, clearance_mm, scene_of
from codegen.world.engine import distance
from codegen.world.sweep import MoveClearance, Unresolved, check_path, joint_path

# A linear move's joints are solved at a grid along the line fine enough that no axis moves more than this between
# neighbouring points, and read between them linearly: the joints so read stay within a small fraction of this of the
# solved path (a smooth path bends by the second order of its step), far below what the clearance's sampling resolves
GRID_STEP_DEG = 0.2
GRID_MAX = 1 << 16


@dataclass(frozen=True)
class Move:
    """A planned move: joint (every axis linear) or linear (the TCP on the straight line to tcp2base), ending at
    joints (deg); where names it in a refusal (program file:line where the writer knows it, else the program and the
    pose); carrying: the part in the gripper along it; stage: the key of the solids that stand only for a while
    (Path.stages), "" none."""

    kind: str
    joints: np.ndarray
    where: str
    tcp2base: np.ndarray | None = None
    carrying: bool = False
    stage: str = ""
    grip: str = ""  # "grip" or "release": the gripper acts at this move's end (the part is taken or put down there)
    # (body, solid) pairs the kind's own check holds on this move instead (a box's own descent among the boxes it is
    # put down flush with)
    exempt: frozenset = frozenset()


@dataclass(frozen=True)
class Path:
    """A program's planned moves on one target's arm from start (joints, deg); the part it carries (a PartShape or a
    Box in the flange frame, None: none) and the solids that stand only for a while, by stage (the stack as built)."""

    target: str
    start: np.ndarray
    moves: tuple[Move, ...]
    part: object = None
    stages: dict = field(default_factory=dict)
    # where the arm's configuration comes from, in the kind's words, for a refusal's fix ("": the program's own)
    configuration: str = ""
    # the kind's own fix for a move too near a solid it knows (fix.text(cell, path, move, solid) -> str, or None:
    # the proof's own below): the fix that follows the move's cause, naming the kind's keys
    fix: object = None


@dataclass(frozen=True)
class Least:
    """The least clearance of a path's moves: the move (where), and the sweep's finding."""

    target: str
    where: str
    found: MoveClearance


class ClearanceError(ValueError):
    """A planned move that comes within the cell's clearance of a solid (or of the arm itself)."""


def prove(cell, paths: list[Path], at_least: float | None = None) -> list[Least]:
    """Each path's least clearance, or ClearanceError naming the first move within the clearance (or within at_least
    mm where that is more: the bar a posture has to clear to be preferred, where a kind chooses one)."""
    limit = clearance_mm(cell)
    bar = limit if at_least is None else max(at_least, limit)
    out = []
    for path in paths:
        out.append(_prove(cell, path, limit, bar))
    return out


def _prove(cell, path: Path, limit: float, bar: float) -> Least:
    scenes: dict = {}

    def scene(carrying: bool, stage: str, exempt: frozenset):
        key = (bool(carrying) and path.part is not None, stage, exempt)
        if key not in scenes:
            part = path.part if key[0] else None
            scenes[key] = scene_of(cell, path.target, part, path.stages.get(stage), exempt)
        return scenes[key]

    arm = cell.robot.arms[path.target]
    tcp2flange = cell.robot.tool.tcp2flange
    exempt = _resting(cell, path, limit, scene)
    q = np.asarray(path.start, dtype=float)
    best: Least | None = None
    for i, move in enumerate(path.moves):
        if move.kind == "linear":
            tcp0 = arm.kin.fk(q) @ tcp2flange
            tcp1 = move.tcp2base if move.tcp2base is not None else arm.kin.fk(move.joints) @ tcp2flange
            route = _linear(arm, tcp2flange, tcp0, tcp1, q, move.where)
        else:
            route = joint_path(q, move.joints)
        try:
            found = check_path(scene(move.carrying, move.stage, exempt[i] | move.exempt), route, q, limit)
        except Unresolved as exc:
            raise ClearanceError(f"{move.where} ({path.target}): the move's path cannot be followed: {exc}") from None
        if found.distance < bar:
            came_from = path.moves[i - 1].where if i else f"the start (joints {_joints_text(path.start)} deg)"
            raise ClearanceError(_refusal(cell, path, move, found, bar, (i, came_from)))
        if best is None or found.distance < best.found.distance:
            best = Least(path.target, move.where, found)
        q = np.asarray(move.joints, dtype=float)
    return best


def _line(tcp0: np.ndarray, tcp1: np.ndarray, s: np.ndarray) -> np.ndarray:
    """(n, 4, 4) TCP poses along a linear move: the position on the straight line, the orientation turned about one
    fixed axis by the fraction s of the whole turn (as codegen.world.sweep.linear_path; Rodrigues' formula)."""
    turn = np.asarray(poses.rotvec_from_rotmat(tcp0[:3, :3].T @ tcp1[:3, :3]), dtype=float)
    angle = float(np.linalg.norm(turn))
    k = np.zeros((3, 3)) if angle == 0.0 else np.cross(np.eye(3), turn / angle)  # the axis' cross-product matrix
    rot = np.eye(3) + np.sin(s * angle)[:, None, None] * k + (1.0 - np.cos(s * angle))[:, None, None] * (k @ k)
    out = np.zeros((len(s), 4, 4))
    out[:, 3, 3] = 1.0
    out[:, :3, :3] = tcp0[:3, :3] @ rot
    out[:, :3, 3] = tcp0[:3, 3] + s[:, None] * (tcp1[:3, 3] - tcp0[:3, 3])
    return out


def _linear(arm, tcp2flange, tcp0, tcp1, q0, where: str):
    """A linear move from joints q0 as the controller continues it: the configuration (the analytic branch) q0 has,
    each axis turned continuously from q0's; solved in one batch on a grid (GRID_STEP_DEG) and read between its
    points. Unresolved where the branch has no solution along the line."""
    q0 = np.asarray(q0, dtype=float)
    _, branch = solve.nearest(arm, solve.branches(arm, arm.kin.fk(q0)[None])[0], q0)
    count = 64
    while True:
        s = np.linspace(0.0, 1.0, count + 1)
        solutions = solve.branches(arm, solve.flange_poses(_line(tcp0, tcp1, s), tcp2flange))[:, int(branch)]
        if np.isnan(solutions).any():
            at = float(s[int(np.argmax(np.isnan(solutions).any(axis=1)))])
            raise Unresolved(f"the linear move leaves the arm's configuration (no solution) at {at:.4f} of its length")
        q = np.vstack([q0, solutions[1:]])
        q = q0 + np.cumsum(np.vstack([np.zeros(6), (np.diff(q, axis=0) + 180.0) % 360.0 - 180.0]), axis=0)
        step = float(np.abs(np.diff(q, axis=0)).max(initial=0.0))
        if step <= GRID_STEP_DEG or count >= GRID_MAX:
            break
        count = min(GRID_MAX, count * max(2, int(np.ceil(step / GRID_STEP_DEG))))
    if step > GRID_STEP_DEG:
        raise Unresolved(f"{where}: an axis turns faster than the grid follows (a singularity on the line)")

    def at(value: float, _near) -> np.ndarray:
        x = value * count
        k = min(int(x), count - 1)
        return q[k] + (x - k) * (q[k + 1] - q[k])

    return at


def _resting(cell, path: Path, limit: float, scene) -> list[frozenset]:
    """Per move, the (body, solid) pairs not measured: where the gripper acts (a grip or a release), the tool and the
    part touch what the part is taken from or put down on (and the part's neighbours there); along the straight
    moves next to that pose, before and after it, the tool and the part are not measured against a solid within the
    clearance of them at that pose, up to the first pose where none of those pairs is within the clearance. Every
    other body, and every other solid, is measured throughout."""
    out: list[frozenset] = [frozenset()] * len(path.moves)
    moves = path.moves

    def near(anchor: int, j: int) -> set[tuple[str, str]]:
        """The (tool or part, solid) pairs within the clearance where move `anchor` ends, with move j's solids and
        load."""
        held = scene(moves[j].carrying, moves[j].stage, frozenset())
        frames = held.arm.kin.link_frames(np.asarray(moves[anchor].joints, dtype=float)[None])[0]
        pairs = set()
        for body in held.bodies:
            if body.name not in ("tool", "part"):
                continue
            for name, solid in zip(held.names, held.solids, strict=True):
                if distance(body.shape, frames[body.frame], solid, np.eye(4))[0] < limit:
                    pairs.add((body.name, name))
        return pairs

    for i, move in enumerate(moves):
        if not move.grip:
            continue
        for step in (-1, 1):  # the moves coming to the pose (i, i - 1, ...) and leaving it (i + 1, ...)
            j = i if step < 0 else i + 1
            while 0 <= j < len(moves) and moves[j].kind == "linear":
                pairs = near(i, j)
                if not pairs:
                    break
                out[j] = out[j] | frozenset(pairs)
                far = j - 1 if step < 0 else j  # the pose at the move's other end
                if far < 0 or not pairs & near(far, j):
                    break
                j += step
    return out


def _joints_text(joints) -> str:
    return "[" + ", ".join(f"{float(v):.1f}" for v in joints) + "]"


def _refusal(cell, path: Path, move: Move, found: MoveClearance, limit: float, came: tuple[int, str]) -> str:
    """The move (its number, its kind, where it comes from and goes to), the body, the solid, how near and where along
    the move, what the proof measured (its samples and their spacing: the module codegen.world.sweep says why no
    contact falls between them) and what would fix it."""
    target = path.target
    arm = cell.robot.arms[target]
    index, came_from = came
    other = found.other
    floor = other == FLOOR
    what = "touches" if found.distance <= 0 else "comes within"
    depth = format_literal(-found.distance, 1)
    at = f"{found.distance:.1f} mm of it" if found.distance > 0 else f"{depth} mm into it"
    solid = f"the solid {other!r}" if not floor else f"the floor (cell.world.floor_z_mm = {cell.world.floor_z_mm:g} mm)"
    if floor and found.distance <= 0:
        what, at = "dips below", f"{depth} mm, its lowest point at z = {format_literal(found.point[2], 1)} mm,"
    if other in {body.name for body in arm_bodies(arm)} | {"tool", "part"}:
        solid = f"the arm's own {other}"
    fix = _fix(cell, path, move, other, solid.startswith("the arm's own"))
    return (
        f"{move.where} ({target}, {arm.model}): the {found.body} {what} {solid}: {at} at {found.s:.2f} of the "
        f"{move.kind} move to it from {came_from} (move {index + 1} of the path; joints there "
        f"{_joints_text(found.joints)} deg), less than the clearance of {limit:g} mm (cell.world.clearance_mm; the "
        f"proof measured the move at {found.samples} samples, no point of the arm travelling more than {limit / 2:g} "
        f"mm between two: no contact falls between them); {fix}"
    )


OWN = "the program's own"  # the configuration a controller takes by its own rule
# a kind whose programs name no configuration: the controller's rule from the home decides it (Path.configuration)
FROM_THE_HOME = "the program names none: the controller takes the solution nearest the home; another home gives another"


def _fix(cell, path: Path, move: Move, other: str, own: bool) -> str:
    """What would fix a move within the clearance, naming the home the arm starts from and the configuration tried."""
    own_fix = None if own or path.fix is None else path.fix.text(cell, path, move, other)
    if own_fix:
        return own_fix
    target = path.target
    home = f"[cell.robot.home] {target} = [{', '.join(f'{v:g}' for v in cell.robot.home[target])}]"
    config = path.configuration or OWN
    if own:
        return f"give the pose another configuration ({config}), or the arm another home than {home}"
    if other == FLOOR:
        end = [round(float(v), 1) for v in move.joints]
        return (
            f"the configuration tried ({config}) ends the move at joints {end} deg from the home {home}: teach the "
            "poses of the move higher, a pose between them that leads the arm above, or give the arm another home or "
            "configuration"
        )
    return (
        f"move {other!r} away from the move's path, teach a pose between that leads the arm around it, or give "
        f"the arm another home than {home} or another configuration ({config})"
    )
