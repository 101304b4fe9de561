"""The configurations a pallet program names: the controller's own from the home, or one posture chosen to clear."""

# The program names a configuration for each joint move (codegen/kinds/pallet/reach.py Named): the ones the controller
# takes from the home by itself where those clear the cell; where they do not, every joint move of the whole cycle in
# one analytic branch, tried nearer the home first and ranked by codegen/world/posture.py (a branch replaces the kept
# one only where it clears by TIE_MM more). Each candidate must pass the reach proof (check_pallet) and the clearance
# proof of every path generate proves (pallet_paths). The program names the choice in each target's own form (joints,
# status and turn bits or configuration data: codegen/robot/config.py FORMS) and verify plans every case with the same
# configurations: both read the kind's plan (codegen/kinds/pallet/plan.py), which decide() below makes. Where the cell
# names the configuration above Q ([pallet.config]), nothing is chosen: the whole cycle is worked in the branch the
# controller's own rule selects there for it, and the proofs refuse it, naming the key, where it does not reach or does
# not clear.

from __future__ import annotations

from dataclasses import replace

import numpy as np

from codegen.kept import Kept, digest
from codegen.kinds.pallet.cycle import ExpectedMove
from codegen.kinds.pallet.interlocks import PalletIO
from codegen.kinds.pallet.reach import PICK_KEY, Named, PalletReach, check_pallet, joints_of, plan
from codegen.kinds.pallet.scene import pallet_paths
from codegen.kinds.pallet.section import Pallet, pallets_of
from codegen.model.cell import Cell
from codegen.model.motion import MotionSettings
from codegen.model.robot import Tool
from codegen.robot import solve
from codegen.robot.config import FORMS
from codegen.robot.taught import ReachError
from codegen.world.posture import TIE_MM, Posture, branch_count, choose, in_order, set_by_the_tool, travel

# decide() reads the whole cell but for these fields (grep: they reach only the program's text and header, its loads,
# verify's timing, the load's warnings and the moves' speeds, which neither the reach proof nor the clearance proof
# reads), so its choice is kept by the value of everything else: a cell that differs only in them (a speed, a mass, a
# timeout, the blending, the file it was read from) reuses the proofs of one that was decided. Cell.plans is the
# cell's own store of plans; the kinds it was loaded with are kept by identity.
UNREAD = {
    Cell: {"plans", "source", "sha256", "warnings"},
    MotionSettings: {"speed_mm_s", "work_speed_mm_s"},
    Tool: {"mass_kg"},
    Pallet: {"box_mass_kg", "zone_mm"},
    PalletIO: {"timeout_s"},
    ExpectedMove: {"speed_mm_s"},
}


# decide's choices (one per pallet and target of the cells a process works with) and each path's least clearance (a
# few per posture tried); an entry holds the named configurations and the proofs' margins (about 2 kB pickled for the
# bundled pallets), or one Least (about 0.5 kB): both stores full, well under 1 MB
DECIDED = Kept(64)
PROVEN = Kept(512)


def decide(cell, pallet, target: str, cycle) -> tuple[Named | None, str, tuple | None]:
    """decide_anew's choice, kept by the value of everything it reads (UNREAD: what it does not)."""
    key, held = decision_key(cell, pallet, target, cycle)
    made = DECIDED.get(key)
    if made is None:
        made = decide_anew(cell, pallet, target, cycle)
        DECIDED.put(key, made, held)
    return made


def decision_key(cell, pallet, target: str, cycle) -> tuple[bytes, list]:
    """The key of decide's choice: the digest of everything it reads."""
    return digest(target, cell, pallet, tuple(cycle), unread=UNREAD)


def path_key(cell, path, bar: float | None) -> tuple[bytes, list]:
    """The key of a path's proof: the digest of the path, the bar, and what the proof reads of the cell."""
    from codegen.world.cell import clearance_mm, solids, tool_shape

    robot = cell.robot
    arm, tcp2flange = robot.arms[path.target], robot.tool.tcp2flange
    return digest(path, bar, clearance_mm(cell), arm, tcp2flange, solids(cell), tool_shape(cell), unread=UNREAD)


def proven(cell, path, bar: float | None):
    """The path's least clearance (codegen/world/proof.py prove, which reads of the cell the arm, the tool and the
    solids), kept by their values and the path's; a refusal is not kept."""
    from codegen.world.proof import prove

    key, held = path_key(cell, path, bar)
    made = PROVEN.get(key)
    if made is None:
        (made,) = prove(cell, [path], bar)
        PROVEN.put(key, made, held)
    return made


def decide_anew(cell, pallet, target: str, cycle) -> tuple[Named | None, str, tuple | None]:
    """The configurations the target's program names for the pallet (None without an arm), the posture note ('' where
    they are the controller's own from the home or the cell's), and the proofs the choice made of them: (the reach
    proof, the clearance proof's least clearances of the pallet's paths), None where it made none. cycle: the
    pallet's full cycle (codegen/kinds/pallet/shape.py full_cycle)."""
    natural = plan(cell, pallet, target, cycle=cycle)
    if natural is None:
        return None, "", None
    if target in pallet.config:
        return _given(cell, pallet, target, natural, cycle), "", None
    home = cell.robot.home[target]
    start = travel(_first(cell, pallet, target, natural, cycle), home)
    first = _evaluate(cell, pallet, target, cycle, Posture(natural, -1, start))
    if not first.reaches or (first.least_mm is not None and set_by_the_tool(cell.robot.arms[target], first.nearest)):
        return natural, "", first.proven  # the reach proof names what is out of reach; no other posture keeps more
    others = _candidates(cell, pallet, target, natural, cycle)
    best = choose(first, others, lambda posture, bar: _evaluate(cell, pallet, target, cycle, posture, bar))
    if best is None:
        return natural, "", None  # none clears: generate's clearance proof refuses the controller's own, naming it
    if best is first:
        return natural, "", first.proven
    return best.config, _note(cell, target, first, best), best.proven


def reach_in(cell, pallet, target: str, named: Named | None, cycle) -> PalletReach:
    """The pallet's reach proof in the configurations its program names; a refusal of the cell's own names its key."""
    try:
        return check_pallet(cell, pallet, target, named, cycle)
    except ReachError as exc:
        if named is None or not named.source:
            raise
        raise ReachError(f"{exc} (in the configuration the cell names: {named.source})") from None


def _given(cell, pallet, target: str, natural: Named, cycle) -> Named:
    """The configurations of the cell's own ([pallet.config]): the whole cycle in the analytic branch that the
    configuration selects above Q by the controller's rule, nothing else tried. ReachError naming the key where it
    selects no solution there or the cycle in that branch reaches Q in another configuration."""
    given = pallet.config[target]
    arm = cell.robot.arms[target]
    source = f"[pallet.config] {target} = {_shown(target, given.form, given.value)} of pallet {pallet.name!r}"
    above = next(m for m in cycle if natural.key(pallet, m) == PICK_KEY)
    solutions = solve.branches(arm, solve.flange_poses(above.tcp2base[None], cell.robot.tool.tcp2flange))[0]
    joints, branch = FORMS[given.form].select(arm, solutions, given.value)
    if np.isnan(joints).any():
        raise ReachError(
            f"{source}: the arm takes no solution in this configuration above Q ({arm.model}, within the joint "
            "limits): name one it takes there, or leave the key out and let generate choose"
        )
    try:
        named = plan(cell, pallet, target, int(branch), cycle)
    except ReachError as exc:
        raise ReachError(f"{exc} (in the configuration the cell names: {source})") from None
    first = _first_above(cell, pallet, target, named, cycle)
    if not np.allclose(first, joints, atol=1e-6):
        kept = _shown(target, named.form, FORMS[named.form].of(arm, first))
        raise ReachError(
            f"{source}: the cycle worked in this configuration's branch comes above Q from the home in {kept} "
            f"(joints {np.round(first, 2).tolist()} deg), not in the one named (joints "
            f"{np.round(joints, 2).tolist()} deg): name that one"
        )
    return replace(named, source=source)


def _first_above(cell, pallet, target: str, named: Named, cycle) -> np.ndarray:
    """The joints of the cycle's first move above Q, as the program names its configuration."""
    moves = cycle
    index = next(i for i, m in enumerate(moves) if named.key(pallet, m) == PICK_KEY)
    return joints_of(cell, target, moves[: index + 1], f"pallet {pallet.name!r}", pallet, named)[-1]


def _shown(target: str, form: str, value) -> str:
    """A configuration (a form's value) as the cell file writes it for the target."""
    from codegen.controllers import get_target

    if form == "status_turn":
        return "{{ s = {}, t = {} }}".format(*value)
    listed = "[" + ", ".join(f"{v:g}" if isinstance(v, float) else str(v) for v in value) + "]"
    return listed if form == get_target(target).configuration else f"{{ {form} = {listed} }}"


def _candidates(cell, pallet, target: str, natural: Named, cycle) -> list[Posture]:
    """Each analytic branch the whole cycle can be worked in (every move reached within it, the linear moves without a
    flip), unless the program would name the same configurations as the controller's own, nearer the home first."""
    home = cell.robot.home[target]
    out = []
    for branch in range(branch_count(cell.robot.arms[target])):
        try:
            named = plan(cell, pallet, target, branch, cycle)
        except ReachError:
            continue
        if named is not None and not _same(named, natural):
            out.append(Posture(named, branch, travel(_first(cell, pallet, target, named, cycle), home)))
    return in_order(out)


def _same(a: Named, b: Named) -> bool:
    """The two name the same configurations (and the same axis values at the fixed poses)."""
    same = a.anchors.keys() == b.anchors.keys()
    anchors = same and all(np.array_equal(a.anchors[k], b.anchors[k]) for k in a.anchors)
    return a.form == b.form and a.whole == b.whole and a.values == b.values and anchors


def _first(cell, pallet, target: str, named: Named, cycle) -> np.ndarray:
    """The joints of the cycle's first move from the home, as the program names it."""
    return joints_of(cell, target, cycle[:1], f"pallet {pallet.name!r}", pallet, named)[0]


def _evaluate(cell, pallet, target: str, cycle, posture: Posture, bar: float | None = None) -> Posture:
    """The posture with its least clearance over every path generate proves for the pallet, or its refusal (reach:
    joint and wrist margins, no flip on a linear move; clearance: within the cell's clearance, or within bar mm); a
    posture that passes both keeps them (proven: the reach proof and the least clearances, equal to the proof's
    without the bar: the bar only refuses more)."""
    from codegen.world.proof import ClearanceError  # coal: loaded only when proving

    try:
        reached = check_pallet(cell, pallet, target, posture.config, cycle)
    except ReachError as exc:
        return replace(posture, refusal=str(exc), reaches=False)
    try:
        paths = pallet_paths(cell, pallets_of(cell), pallet, target, posture.config, cycle)
        least = [proven(cell, path, bar) for path in paths]
    except (ClearanceError, ReachError, ValueError) as exc:
        return replace(posture, refusal=str(exc))
    nearest = min(least, key=lambda x: x.found.distance)
    return replace(posture, least_mm=nearest.found.distance, nearest=nearest, proven=(reached, tuple(least)))


def _note(cell, target: str, first: Posture, best: Posture) -> str:
    from codegen.controllers import get_target

    arm = cell.robot.arms[target]
    form = get_target(target).configuration
    why = "does not clear"
    if first.least_mm is not None:
        why = f"keeps {first.least_mm:.1f} mm (more than {TIE_MM:g} mm less)"
    return (
        f"posture chosen to clear the cell: every joint move in the arm's configuration {best.branch} "
        f"({arm.model}'s analytic branch, named as {form}), least clearance {best.least_mm:.1f} mm; the configuration "
        f"nearest the home [cell.robot.home] {target} = [{', '.join(f'{v:g}' for v in cell.robot.home[target])}] {why}"
    )
