"""The whole stack proven reachable at generate time: every move of a full cycle solved for the cell's arm."""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np

from codegen.controllers import get_target
from codegen.kinds.pallet.cycle import SAFE_NAME, ExpectedMove
from codegen.kinds.pallet.shape import full_cycle, pallet_shape, shape
from codegen.kinds.pallet.stack import pattern_of
from codegen.robot import solve
from codegen.robot.config import FORMS, loose, named_in_full
from codegen.robot.expect import JOINT_TOLERANCE_DEG, Margins, margins, require_margins
from codegen.robot.margins import wrist_angle
from codegen.robot.taught import ReachError


@dataclass(frozen=True)
class PalletReach(Margins):
    """One pallet on one target's arm: the least margins over a full cycle's moves."""

    pallet: str = ""
    moves: int = 0
    posture: str = ""  # the posture chosen to clear the cell where it is not the one nearest the home (else "")

    def subject(self) -> tuple[str, int, str]:
        return f"pallet {self.pallet}", self.moves, "moves"

    def keys(self) -> dict:
        return {"pallet": self.pallet, "moves": self.moves, "posture": self.posture}

    def text(self) -> str:
        return super().text() + (f"\n    {self.posture}" if self.posture else "")


# The configuration keys of the joint moves (a box's entry: its pattern and number)
PICK_KEY = "Q"  # above Q
SHEET_KEY = "sheet stack"  # above the slip sheets' stack
SHEET_ENTRY_KEY = "sheet entry"  # above a slip sheet's place on the pallet
SAFE_KEY = "safe"  # above the pallet's centre, on the way home after a stop


@dataclass(frozen=True)
class Named:
    """The configurations a pallet program names, in the target's form (codegen/robot/config.py FORMS):
    per box of a pattern (pattern name, box number) the one its entry takes (the joint move onto the
    pallet), and Q's (the joint move above Q)."""

    form: str
    values: dict  # (pattern, number) or PICK_KEY -> the form's value
    whole: bool = True  # the program names every field; else only the form's kept ones (config.Form)
    # where the program names no configuration in full: the fixed poses its joint moves go to (above Q, above the
    # sheet stack, the safe pose) as axis values (key -> joints): each move from one of them has one nearest
    # solution, whatever the turns the arm took before (no axis winds up from box to box)
    anchors: dict = field(default_factory=dict)
    # where the cell names the configuration ([pallet.config]): that key as a refusal's fix names it ("": chosen)
    source: str = ""

    def anchor(self, move) -> object:
        """The anchor of a joint move to a fixed pose the program names in axis values, None: another move."""
        key = anchor_key(move)
        return key if key in self.anchors else None

    def key(self, pallet, move) -> object:
        """The configuration key of a joint move (by its reference name), None: a move that names none."""
        if move.kind != "joint":
            return None
        if move.name.endswith(("above Q", "over Q")):
            return PICK_KEY
        if move.name == SAFE_NAME:
            return SAFE_KEY
        words = move.name.split()
        if words[0] != "layer":
            return None
        if words[2] == "sheet":
            return SHEET_KEY if move.name.endswith("sheet stack") else SHEET_ENTRY_KEY
        return (pattern_of(pallet, int(words[1])), int(words[3])) if words[-1] in ("entry", "transit") else None


def anchor_key(move, any_motion: bool = False) -> object:
    """The key of a joint move to one of the fixed poses (above Q, above the sheet stack, the safe pose), None:
    another move (a box's entry or transit, over Q at a layer's height: computed while the program runs);
    any_motion: a linear move there too (where the cycle reaches the pose, e.g. unstacking's way down to Q)."""
    if move.kind != "joint" and not any_motion:
        return None
    if move.name.endswith("above Q"):
        return PICK_KEY
    if move.name.endswith("above the sheet stack"):
        return SHEET_KEY
    return SAFE_KEY if move.name == SAFE_NAME else None


def _branch(arm, joints: np.ndarray) -> int:
    """The analytic branch (configuration) of given joints."""
    solutions = solve.branches(arm, arm.kin.fk(joints)[None])[0]
    _, chosen = solve.nearest(arm, solutions, joints)
    return int(chosen)


def joints_of(
    cell, target: str, moves, where: str, pallet=None, named: Named | None = None, start=None, within=None
) -> list[np.ndarray]:
    """Each move's joints for the target's arm with the cell's tool, from home (or the start joints): a joint
    move to a pose the program names a configuration for (named) takes the solution of that configuration (the
    controller's rule: codegen/robot/config.py), another joint move the solution nearest the joints before it (the
    rule where the program names none; within: in that analytic branch only, a posture tried for the whole
    cycle); a linear move keeps the configuration (its branch) and may not jump. ReachError names the move."""
    robot = cell.robot
    arm = robot.arms[target]
    poses = np.array([m.tcp2base for m in moves]).reshape(-1, 4, 4)
    flange2base = solve.flange_poses(poses, robot.tool.tcp2flange)
    solutions = solve.branches(arm, flange2base)
    if within is not None:  # the other branches' solutions left out
        solutions = np.where((np.arange(solutions.shape[1]) == within)[None, :, None], solutions, np.nan)
    q = np.asarray(robot.home[target] if start is None else start, dtype=float)
    branch, out = None if start is None else _branch(arm, q), []
    for move, sols, flange in zip(moves, solutions, flange2base, strict=True):
        at = f"{where} {move.name} ({target}, {arm.model})"
        key = None if named is None else named.key(pallet, move)
        anchor = None if named is None else named.anchor(move)
        if anchor is not None:  # a joint target: the axis values the program names
            joints, chosen = FORMS["joints"].select(arm, sols, named.anchors[anchor])
        elif key is not None and key in named.values and not named.whole:
            try:
                joints, chosen = loose(named.form, arm, sols, named.values[key], q)
            except ValueError as exc:
                raise ReachError(
                    f"{at}: {exc}: which way the controller turns is decided by rounding (the program names no "
                    "turn at a vertical tool); turn [cell.robot.home]'s axis a few degrees toward the side the arm "
                    "should take"
                ) from None
        elif key is not None and key in named.values:
            joints, chosen = FORMS[named.form].select(arm, sols, named.values[key])
            if np.isnan(joints).any():
                raise ReachError(
                    f"{at}: no solution in the configuration {_text(named.values[key])} the program names for it "
                    f"(chosen where the full cycle first reaches the box): the arm's configuration changes "
                    "between layers; move the pallet or change the tool's orientation"
                )
        else:
            joints, chosen = solve.nearest(arm, sols, q)
        if np.isnan(joints).any():
            raise ReachError(f"{at}: out of reach: {solve.unreachable_text(arm, flange)}")
        if move.kind == "linear" and (int(chosen) != branch or np.max(np.abs(joints - q)) > 90.0):
            raise ReachError(
                f"{at}: the linear move would change the arm's configuration: {flip_text(arm, q, joints)}; "
                f"{_flip_fix(move.name)}"
            )
        out.append(joints)
        q, branch = joints, int(chosen)
    return out


# The cell keys that move a linear move's poses, by the words of the move's reference name (the first found)
FLIP_FIXES = (
    ("sheet", "move the slip sheets' stack ([pallet.slip_sheet] pick)"),
    ("Q", "move Q ([[pallet]] pick) or turn the tool at it (pick's rotation)"),
    ("", "move the pallet ([[pallet]] frame) or turn the tool on it ([[pallet]] tool_orientation)"),
)


def _flip_fix(name: str) -> str:
    words = name.split()
    fix = next(text for word, text in FLIP_FIXES if not word or word in words)
    return f"{fix} so that the arm keeps its configuration along the move"


def flip_text(arm, before: np.ndarray, after: np.ndarray) -> str:
    """Which joint a linear move's flip crosses, with its values: axis 5 through the wrist's singularity (its
    kinematic angle changes side of 0 or 180 deg), else the axis that turns most (the elbow or shoulder)."""
    sides = np.sign(np.sin(np.radians(wrist_angle(arm, np.array([before, after])))))
    axis = 4 if sides[0] != sides[1] else int(np.argmax(np.abs(after - before)))
    what = "crosses the wrist singularity (axes 4 and 6 in line)" if axis == 4 else "turns (an elbow or shoulder flip)"
    return f"axis {axis + 1} {what}: from {before[axis]:.1f} to {after[axis]:.1f} deg"


def _text(value) -> str:
    return "[" + ", ".join(f"{v:.4f}" if isinstance(v, float) else str(v) for v in value) + "]"


def plan(cell, pallet, target: str, branch: int | None = None, cycle=None) -> Named | None:
    """The configurations a pallet program would name in one posture: each box's (pattern, number) that of its entry
    where the full cycle first reaches it from home by the nearest rule (stacking: the lowest layer using the pattern;
    unstacking: the highest), Q's at the first time above Q, the safe pose's the one nearest the first entry's joints;
    branch: every joint move within that analytic branch (None: the controller's own nearest solutions); None without
    an arm. cycle: the pallet's full cycle where the caller has it (codegen/kinds/pallet/posture.py chooses among the
    postures once per cell and target, for the kind's plan)."""
    form = get_target(target).configuration
    if cell.robot is None or target not in cell.robot.arms or form not in FORMS:
        return None
    arm = cell.robot.arms[target]
    moves = full_cycle(cell, pallet) if cycle is None else cycle
    named, values, entry, at, first = Named(form, {}), {}, None, [], {}
    planned = joints_of(cell, target, moves, f"pallet {pallet.name!r}", within=branch)
    for move, joints in zip(moves, planned, strict=True):
        key = named.key(pallet, move)
        if key is not None:
            at.append(joints)  # every joint move's joints: where its configuration must hold
        if key is not None and key not in values:
            values[key] = FORMS[form].of(arm, joints)
        if entry is None and isinstance(key, tuple):
            entry = joints
        anchor = anchor_key(move, any_motion=True)
        if anchor is not None and anchor not in first:
            first[anchor] = joints
    # the way home's pose above the pallet: the solution nearest the cycle's first entry onto the pallet (its
    # branch, each axis' turn as the cycle has it), so the way there from the pallet turns no axis the long way
    safe = [safe_move(cell, pallet)]
    at.append(joints_of(cell, target, safe, f"pallet {pallet.name!r}", start=entry, within=branch)[0])
    values[SAFE_KEY] = FORMS[form].of(arm, at[-1])
    # one rule for the whole program: where any joint move's configuration lies on a boundary (a vertical
    # tool), the program names none in full and each joint move takes the controller's rule without it
    try:
        whole = named_in_full(form, arm, np.array(at))
    except ValueError as exc:
        raise ReachError(f"pallet {pallet.name!r} ({target}, {arm.model}): {exc}") from None
    if whole:
        return Named(form, values, True)
    return Named(form, values, False, _anchors(cell, target, moves, pallet, Named(form, values, False), first, at[-1]))


def _anchors(cell, target: str, moves, pallet, named: Named, first: dict, safe: np.ndarray) -> dict:
    """The fixed poses' axis values: where the cycle first reaches each, an axis that stands half a turn or more
    from 0 taken on whichever side (one turn apart, within the limits) keeps the whole cycle farthest from the
    joint limits (from home the side of a half turn is a tie: the plan picks it, the program names it)."""
    arm = cell.robot.arms[target]
    options = []
    for key, q in first.items():
        turns = [q]
        for axis in range(6):
            for step in (-solve.TURN, solve.TURN):
                other = q.copy()
                other[axis] += step
                if abs(q[axis]) >= 179.0 and solve.inside_float(other.tolist(), arm.limits_deg):
                    turns.append(other)
        options.append([(key, t) for t in turns])
    best, best_margin = {**first, SAFE_KEY: safe}, -np.inf
    where = f"pallet {pallet.name!r}"
    for choice in itertools.product(*options):
        anchors = {**dict(choice), SAFE_KEY: safe}
        trial = Named(named.form, named.values, False, anchors)
        try:
            planned = joints_of(cell, target, moves, where, pallet, trial)
            # the safe pose in the turns this cycle has: nearest its first entry onto the pallet (the way home
            # from the pallet, and a restart with a held item onto it, turn no axis a full turn)
            entry = next(q for m, q in zip(moves, planned, strict=True) if isinstance(trial.key(pallet, m), tuple))
            anchors[SAFE_KEY] = joints_of(cell, target, [safe_move(cell, pallet)], where, start=entry)[0]
        except ReachError:
            continue
        margin = margins(arm, np.array([*planned, anchors[SAFE_KEY]]))[0]
        if margin > best_margin:
            best, best_margin = anchors, margin
    return best


def way_up_z(cell) -> float:
    """How high (base z, mm) the way home rises straight up before its joint move to the safe pose: the highest of
    the safe poses of the cell's pallets (each at the transit height over its full stack), so the arm, with or
    without a box, swings over any of the arm's pallets, full or not, wherever a stop left it."""
    return shape(cell).way_up_z


def safe_move(cell, pallet):
    """The way home's joint move above the pallet's centre (tcp2base)."""
    return ExpectedMove(
        kind="joint",
        tcp2base=pallet_shape(cell, pallet).safe2base,
        name=SAFE_NAME,
        speed_mm_s=cell.motion.speed_mm_s,
        exact=True,
    )


def check_pallet(cell, pallet, target: str, named: Named | None, cycle=None) -> PalletReach:
    """Every move of a full cycle for the target's arm with the cell's tool, from home, as the program
    moves: a joint move in the configuration the program names for it (named), a linear move
    keeping the arm's configuration (its branch) without a jump; each pose within the cell's joint and
    wrist margins (cycle: the pallet's full cycle where the caller has it). ReachError names pallet, target, box and
    pose."""
    robot = cell.robot
    arm = robot.arms[target]
    moves = full_cycle(cell, pallet) if cycle is None else cycle
    worst_joint, worst_wrist, worst, wrist_pose, named_deg = np.inf, np.inf, "", "", np.inf
    planned = joints_of(cell, target, moves, f"pallet {pallet.name!r}", pallet, named)
    moves = [*moves, safe_move(cell, pallet)]  # and the way home's pose above the pallet, as named
    planned += joints_of(cell, target, moves[-1:], f"pallet {pallet.name!r}", pallet, named)
    for move, joints in zip(moves, planned, strict=True):
        joint, wrist = margins(arm, joints)
        if joint < named_deg - JOINT_TOLERANCE_DEG:  # a tie keeps the first in stacking order, as verify's report
            worst, named_deg = move.name, joint
        worst_joint = min(worst_joint, joint)
        if wrist < worst_wrist:
            worst_wrist, wrist_pose = wrist, move.name
    subject = f"pallet {pallet.name!r} ({target}, {arm.model})"
    fix = "place the pallet (its frame) farther from or nearer to the arm's base, or higher or lower"
    require_margins(subject, robot, worst_joint, worst_wrist, worst, wrist_pose, fix)
    return PalletReach(
        target, arm.model, worst_joint, worst_wrist, worst, wrist_pose, pallet=pallet.name, moves=len(moves)
    )
