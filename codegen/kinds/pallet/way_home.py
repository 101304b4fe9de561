"""The pallet program's way home after a stop anywhere, as the reference plans it: back along the tool, up to the
transit height, over to the safe pose, home."""

from __future__ import annotations

import numpy as np

from codegen.kinds.pallet.cycle import ExpectedMove, risen
from codegen.kinds.pallet.reach import joints_of, safe_move, way_up_z
from codegen.verify.plan import PlannedMove


def way_home(cell, pallet, target, home, start, layer: int) -> list[PlannedMove]:
    """From where the arm starts: at home, the move home; elsewhere (a stop in the cycle) the way home: (a joint move
    where the arm stands, where the target's first motion must be one), back along the tool's z by the cell's
    retreat_mm, straight up to the transit height over the layer the counters name (at the pallet's centre; kept
    where it is higher already), above the pallet's centre, home."""
    tcp2flange = cell.robot.tool.tcp2flange
    percent = cell.motion.joint_speed_percent
    home_planned = PlannedMove(
        name="home", kind="joint", tcp2base=home[0].tcp2base, exact=True, joint_percent=percent, joints=home[1]
    )
    q = np.asarray(start, dtype=float)
    if np.max(np.abs(q - home[1])) <= cell.motion.start_tolerance_deg:
        return [home_planned]
    arm = cell.robot.arms[target.name]
    here = arm.kin.fk(q) @ tcp2flange
    back = here @ np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, -cell.motion.retreat_mm], [0, 0, 0, 1.0]])
    # the first motion a joint move where the arm stands (a BCO run; on every controller the arm's joints are then
    # the path's start: the retreat keeps its configuration)
    way = [
        PlannedMove(
            name="where the arm stands", kind="joint", tcp2base=here, exact=True, joint_percent=percent, joints=q
        )
    ]
    way.append(
        PlannedMove(
            name="back along the tool's z",
            kind="linear",
            tcp2base=back,
            exact=True,
            speed_mm_s=cell.motion.work_speed_mm_s,
        )
    )
    up = risen(back, way_up_z(cell))  # over every pallet of the arm, full or not
    way.append(
        PlannedMove(
            name="up to the transit height",
            kind="linear",
            tcp2base=up,
            exact=True,
            speed_mm_s=cell.motion.work_speed_mm_s,
        )
    )
    safe = safe_move(cell, pallet)
    way.append(
        PlannedMove(
            name=safe.name,
            kind="joint",
            tcp2base=safe.tcp2base,
            exact=True,
            speed_mm_s=safe.speed_mm_s,
            joint_percent=percent,
        )
    )
    return [*way, home_planned]


def way_joints(
    cell, pallet, target_name: str, way: list[PlannedMove], start, named, where: str = "verify: the way home"
) -> list:
    """The way home's joints before home: where the arm stands (a joint move there), the retreat keeping its
    configuration, the safe pose in the configuration the program names (where: the way home's name in a refusal)."""
    head = [np.asarray(start, dtype=float)] if way[0].kind == "joint" else []
    rest = [
        ExpectedMove(kind=m.kind, tcp2base=m.tcp2base, name=m.name, speed_mm_s=m.speed_mm_s or 0.0, exact=True)
        for m in way[len(head) :]
    ]
    return [*head, *joints_of(cell, target_name, rest, where, pallet, named, start=start)]


def joint_percent(cell, move) -> float | None:
    return cell.motion.joint_speed_percent if move.kind == "joint" else None
