"""The pallets in the cell: as the page draws them (each pallet, its boxes layer by layer, slip sheets, pick place)
and as solids (the pallet, the pick place and the stack as built)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from codegen.kinds.pallet.patterns import label_normal
from codegen.kinds.pallet.refusals import StackFix
from codegen.kinds.pallet.shape import PalletShape, full_cycle, pallet_shape
from codegen.kinds.pallet.sweep import PLACE_POSES, _own
from codegen.poses import matrix_from_rotation_translation, rotmat_from_zyx_deg
from codegen.protocol import Stage
from codegen.view.scene import SLAB_MM, box, frame, translated
from codegen.world.proof import Move, Path
from codegen.world.solids import Box

PALLET_HEIGHT_MM = 144.0  # a EUR pallet's height (EN 13698-1): the pallet's solid under its top
PICK_PLACE_SCALE = 1.5  # the pick place's top reaches this many box sizes around Q (as the page draws it)
PICK_PLACE_DEPTH_MM = 100.0  # the pick place's solid under its top: the top plate of what holds the box at Q

# the configuration the proofs try (codegen/kinds/pallet/posture.py), for a refusal's fix
PALLET_CONFIGURATION = "the controller's own from the home, else each analytic branch for the whole cycle that reaches"

LABEL_MM = 1.0  # a box's label, drawn as a sheet this thick on its label side
GAP_MM = 2.0  # boxes drawn this much narrower than they are, so that neighbours show apart


def objects(cell, pallets) -> list[dict]:
    out = []
    for pallet in pallets:
        out += _pallet(pallet_shape(cell, pallet))
    return out


def _pallet(shape: PalletShape) -> list[dict]:
    """The pallet (its top at the frame's z = 0), every box of the full stack with its label right after it (the
    page's box events rely on that order), the slip sheets and the pick place Q."""
    pallet, pallet2base = shape.pallet, shape.pallet2base
    length, width = pallet.size
    out = [
        box(translated(pallet2base, (length / 2, width / 2, -SLAB_MM / 2)), (length, width, SLAB_MM), "wood"),
        frame(pallet2base, f"pallet {pallet.name}", "wood", 120.0),
    ]
    bx, by, bz = pallet.box
    face = by / 2 - GAP_MM / 2 + LABEL_MM / 2
    for p in shape.placements:
        top = shape.tops[p.layer]
        turn = rotmat_from_zyx_deg(p.box.ccw_deg, 0.0, 0.0)
        centre = pallet2base @ matrix_from_rotation_translation(turn, (p.box.x, p.box.y, top - bz / 2))
        size = (bx - GAP_MM, by - GAP_MM, bz)
        out.append(box(centre, size, "box", f"{pallet.name}: layer {p.layer} box {p.number}"))
        nx, ny = label_normal(p.box)  # the label on the long side at -y at angle 0
        label = pallet2base @ matrix_from_rotation_translation(
            turn, (p.box.x + nx * face, p.box.y + ny * face, top - bz / 2)
        )
        out.append(box(label, (bx * 0.5, LABEL_MM, bz * 0.5), "label"))
    if pallet.slip_every:
        for layer in range(pallet.slip_every, pallet.layers, pallet.slip_every):
            z = shape.tops[layer] + pallet.slip_thickness / 2
            sheet = translated(pallet2base, (length / 2, width / 2, z))
            out.append(box(sheet, (length, width, max(pallet.slip_thickness, 1.0)), "sheet", f"slip sheet {layer}"))
    if pallet.pick is not None:
        pick = pallet.pick.matrix()
        out.append(frame(pick, f"pallet {pallet.name}: pick Q", "pick"))
        table = np.eye(4)
        table[:3, 3] = pick[:3, 3] - (0.0, 0.0, bz + SLAB_MM / 2)
        out.append(box(table, (bx * 1.5, by * 1.5, SLAB_MM), "pick", "pick place"))
    return out


def solids(cell, pallets) -> dict[str, Box]:
    """Each pallet (its top at the frame's z = 0, PALLET_HEIGHT_MM deep) and its pick place (a plate whose top is a
    box's height under Q, where the box Q holds stands). The stack is not among them: it grows while the program
    runs (stack_solids)."""
    out = {}
    for pallet in pallets:
        length, width = pallet.size
        centre = translated(pallet_shape(cell, pallet).pallet2base, (length / 2, width / 2, -PALLET_HEIGHT_MM / 2))
        out[f"pallet {pallet.name}"] = Box((length, width, PALLET_HEIGHT_MM), centre)
        if pallet.pick is not None:
            bx, by, bz = pallet.box
            plate = np.eye(4)
            plate[:3, 3] = pallet.pick.matrix()[:3, 3] - (0.0, 0.0, bz + PICK_PLACE_DEPTH_MM / 2)
            size = (bx * PICK_PLACE_SCALE, by * PICK_PLACE_SCALE, PICK_PLACE_DEPTH_MM)
            out[f"pallet {pallet.name}: pick place"] = Box(size, plate)
    return out


def stack_solids(shape: PalletShape, boxes: int) -> dict[str, Box]:
    """The stack with its first `boxes` boxes on the pallet (in placing order; unstacking takes the last first):
    every full layer below the top one as one box over the pallet's area and the layer's height (a bound of its
    boxes, the overhang added), the top layer's boxes each as placed."""
    placed = shape.placements[:boxes]
    if not placed:
        return {}
    pallet, pallet2base = shape.pallet, shape.pallet2base
    length, width = pallet.size
    bx, by, bz = pallet.box
    top_layer = placed[-1].layer
    out = {}
    if top_layer > 1:
        below = shape.tops[top_layer - 1]
        grow = 2 * pallet.overhang_mm
        centre = translated(pallet2base, (length / 2, width / 2, below / 2))
        out[f"pallet {pallet.name}: stack below layer {top_layer}"] = Box((length + grow, width + grow, below), centre)
    top = shape.tops[top_layer]
    for p in placed:
        if p.layer != top_layer:
            continue
        turn = rotmat_from_zyx_deg(p.box.ccw_deg, 0.0, 0.0)
        centre = pallet2base @ matrix_from_rotation_translation(turn, (p.box.x, p.box.y, top - bz / 2))
        out[f"pallet {pallet.name}: layer {p.layer} box {p.number}"] = Box((bx, by, bz), centre)
    return out


def _others(cell, pallets, pallet) -> dict[str, Box]:
    """The other pallets' stacks as a bound: each one full (the most it holds while this pallet is worked)."""
    out = {}
    for other in pallets:
        if other is not pallet:
            shape = pallet_shape(cell, other)
            out.update(stack_solids(shape, shape.boxes))
    return out


def pallet_paths(cell, pallets, pallet, target: str, named, cycle=None) -> list[Path]:
    """The pallet's full cycle on the target's arm from home, as its reach proof plans it (named: the configurations
    its program names, codegen/kinds/pallet/posture.py), with the stack as built before each move and the box carried
    from the grip to the release; then the way home after a stop at the first and at the last box's place (the box
    held), as the program plans it: back along the tool, up to the transit height, above the pallet's centre, home;
    and, unstacking, a box held at the start (a stop between the grip and Q) carried from home and put down at Q, then
    the stack taken off (cycle: the pallet's full cycle where the caller has it)."""
    from codegen.kinds.pallet.cycle import PalletCase
    from codegen.kinds.pallet.restart import expected

    shape = pallet_shape(cell, pallet)
    stacking = pallet.mode == "stack"
    count = 0 if stacking else shape.boxes
    others = _others(cell, pallets, pallet)
    home = np.asarray(cell.robot.home[target], dtype=float)
    part = carried_box(cell, pallet)
    cycle = full_cycle(cell, pallet) if cycle is None else cycle
    fix = StackFix(pallet, tuple(p.name for p in pallets))
    planned, stages = _planned(cell, pallet, target, cycle, named, count, others)
    out = [Path(target, home, tuple(planned), part, stages, _configuration(named), fix)]
    for k in sorted({_first_target(planned), _last_target(planned)} - {None}):
        out.append(_way_home(cell, pallet, target, planned[k], home, part, stages, named, fix))
    keys = [item.key for item in shape.items]
    if not stacking and keys:  # a box held at the start, the counters at the first item: the whole stack stands
        held = expected(cell, pallet, PalletCase("held_at_start", *keys[0], closed=True)).moves
        planned, stages = _planned(cell, pallet, target, held, named, count, others)
        out.append(Path(target, home, tuple(planned), part, stages, _configuration(named), fix))
    return out


def _configuration(named) -> str:
    """The configuration the proofs try, for a refusal's fix: the one the cell names, else the posture's search."""
    return getattr(named, "source", "") or PALLET_CONFIGURATION


def _planned(cell, pallet, target: str, moves, named, count: int, others: dict) -> tuple[list[Move], dict]:
    """The reference's moves as the proof sweeps them: each with its joints, the stack as built before it (`count`
    boxes on the pallet at the first; a confirmed release on its place adds one, a grip there takes one off), the box
    carried from the grip to the release, and the box's own descent onto its place exempt from the stack."""
    from codegen.kinds.pallet.reach import joints_of

    joints = joints_of(cell, target, moves, f"pallet {pallet.name!r}", pallet, named)
    shape = pallet_shape(cell, pallet)
    stacking = pallet.mode == "stack"
    stages: dict[str, dict] = {}
    planned = []
    for i, (move, q) in enumerate(zip(moves, joints, strict=True)):
        after = moves[i + 1].carrying if i + 1 < len(moves) else move.carrying
        grip = "grip" if after and not move.carrying else "release" if move.carrying and not after else ""
        stage = str(count)
        if stage not in stages:
            stages[stage] = {**stack_solids(shape, count), **others}
        where = f"pallet {pallet.name!r} {move.name}"
        own = _own_descent(pallet, stages[stage]) if _own(move.name)[1] in PLACE_POSES else frozenset()
        planned.append(Move(move.kind, q, where, move.tcp2base, move.carrying, stage, grip, own))
        if grip == "release" and stacking and move.name.endswith("target"):
            count += 1
        if grip == "grip" and not stacking and move.name.endswith("target"):
            count -= 1
    return planned, stages


def _own_descent(pallet, stack: dict) -> frozenset:
    """A box's (a slip sheet's) own descent onto its place and the gripper's way up from it (entry, approach,
    target, retreat): the box is put down flush with its layer's boxes and on the layer below, which the pallet's
    own sweep check holds (codegen/kinds/pallet/sweep.py: never below the tops of the boxes under it); the tool and
    the box are not measured against the stack there (every other solid is)."""
    own = [name for name in stack if name.startswith(f"pallet {pallet.name}: ")] + [f"pallet {pallet.name}"]
    return frozenset((body, solid) for body in ("tool", "part") for solid in own)


def _linear_only(move, own: frozenset) -> frozenset:
    return own if move.kind == "linear" else frozenset()


def _box2tcp(pallet) -> np.ndarray:
    """The carried box's centre in the TCP frame: hanging along the tool's z from the middle of its top face."""
    return translated(np.eye(4), (0.0, 0.0, pallet.box[2] / 2))


def _first_target(moves) -> int | None:
    return next((i for i, m in enumerate(moves) if m.where.endswith("target")), None)


def _last_target(moves) -> int | None:
    return next((i for i in range(len(moves) - 1, -1, -1) if moves[i].where.endswith("target")), None)


def _way_home(cell, pallet, target: str, stop: Move, home, part, stages, named, fix) -> Path:
    """The way home the program plans after a stop at `stop`'s pose, the box held as it was there."""
    from codegen.kinds.pallet.way_home import way_home, way_joints
    from codegen.reference import home_move

    start = np.asarray(stop.joints, dtype=float)
    way = way_home(cell, pallet, SimpleNamespace(name=target), home_move(cell, target), start, 0)
    label = f"pallet {pallet.name!r} the way home from {stop.where.split(' ', 2)[2]}"
    joints = way_joints(cell, pallet, target, way[:-1], start, named, f"{label}:")
    # where the stop left the box (the gripper) on its place: back along the tool and up, as its own way up
    own = _own_descent(pallet, stages[stop.stage])
    moves = [
        Move(m.kind, q, f"{label}: {m.name}", m.tcp2base, stop.carrying, stop.stage, exempt=_linear_only(m, own))
        for m, q in zip(way[:-1], joints, strict=True)
    ]
    moves.append(Move("joint", home, f"{label}: home", None, stop.carrying, stop.stage))
    moves = tuple(moves[1:] if moves[0].kind == "joint" else moves)
    return Path(target, start, moves, part, stages, _configuration(named), fix)


def carried_box(cell, pallet) -> Box:
    """The pallet's box in the gripper, in the flange frame: hanging along the tool's z from the middle of its top."""
    return Box(tuple(pallet.box), np.asarray(cell.robot.tool.tcp2flange) @ _box2tcp(pallet))


def case_stages(cell, pallets, index: int, case):
    """Along a verify case's run of pallet `index`: (grips, releases so far) -> Stage. The stack starts as the
    counters the program works from leave it (the reference's: after a reset or the operator's answer); stacking,
    each release puts the next item down, unstacking each grip takes the next one off; the other pallets' stacks
    full; past the items of the pallet the run starts on, a swapped pallet's (stacking, from its first grip;
    unstacking, full from the last release of the done one's). The part is the box (a slip sheet in the gripper is
    not swept, as generate's proof leaves it, nor a box lost on its way); along its descent onto the stack (and the
    way up from it) the pallet's own sweep check holds the tool and the box against that pallet and its stack, as in
    generate's proof (_own_descent)."""
    from codegen.kinds.pallet.cycle import done_counters
    from codegen.kinds.pallet.restart import expected

    pallet = pallets[index]
    shape = pallet_shape(cell, pallet)
    todo = shape.items
    keys = [item.key for item in todo]
    start = expected(cell, pallet, case).start
    done = keys.index(start) if start in keys else len(keys) if start == done_counters(pallet) else 0
    stacking, total = pallet.mode == "stack", shape.boxes
    others, box = _others(cell, pallets, pallet), carried_box(cell, pallet)
    stages: dict[tuple[int, bool], Stage] = {}

    first = len(todo) - done  # the items of the pallet the run starts on; past them, a swapped pallet's

    def stage(grips: int, releases: int) -> Stage:
        swapped = case.exchanges > 0 and (grips > first if stacking else releases >= first > 0)
        worked = todo[: releases - first] if swapped and stacking else todo[: grips - first] if swapped else None
        worked = worked if worked is not None else todo[: done + (releases if stacking else grips)]
        boxes = sum(1 for item in worked if item.placement is not None)
        boxes = boxes if stacking else total - boxes
        at = releases - first if swapped else done + releases
        sheet = stacking and at < len(todo) and todo[at].placement is None
        gone = case.lost and grips > 0  # the box slips out on its way (where is not known): the tool alone from then
        key = (index, boxes, sheet or gone)
        if key not in stages:
            stack = stack_solids(shape, boxes)
            part = None if sheet or gone else box
            stages[key] = Stage(key, {**stack, **others}, part, _own_descent(pallet, stack))
        return stages[key]

    return stage
