"""The whole stack proven reachable at generate time: every move of a full cycle solved for the cell's arm."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from codegen.pallet.cycle import PalletCase, expected, layer_counts
from codegen.robot import solve
from codegen.robot.expect import margins
from codegen.robot.taught import ReachError


@dataclass(frozen=True)
class PalletReach:
    """One pallet on one target's arm: the least margins over a full cycle's moves."""

    target: str
    model: str
    pallet: str
    moves: int
    joint_margin_deg: float
    wrist_margin_deg: float
    worst: str  # the move with the least joint margin

    def text(self) -> str:
        return (
            f"{self.target} ({self.model}) pallet {self.pallet}: {self.moves} moves reachable; "
            f"{self.joint_margin_deg:.1f} deg to the nearest joint limit ({self.worst}), "
            f"wrist {self.wrist_margin_deg:.1f} deg from its singularity"
        )

    def as_json(self) -> dict:
        return {
            "target": self.target,
            "model": self.model,
            "pallet": self.pallet,
            "moves": self.moves,
            "joint_margin_deg": self.joint_margin_deg,
            "wrist_margin_deg": self.wrist_margin_deg,
        }


def full_cycle(cell, pallet):
    """The moves of a whole stack (or unstack) from its first box, as the reference has them."""
    first = (1, 1) if pallet.mode == "stack" else (pallet.layers, layer_counts(pallet)[pallet.layers])
    return expected(cell, pallet, PalletCase("full", *first)).moves


def joints_of(cell, target: str, moves, where: str) -> list[np.ndarray]:
    """Each move's joints for the target's arm with the cell's tool, from home: a joint move takes the
    solution nearest the joints before it (the controllers' rule where the program names no
    configuration), a linear move keeps the configuration (its branch) and may not jump. ReachError names
    the move."""
    robot = cell.robot
    arm = robot.arms[target]
    poses = np.array([m.tcp2base for m in moves]).reshape(-1, 4, 4)
    solutions = solve.branches(arm, solve.flange_poses(poses, robot.tool.tcp2flange))
    q, branch, out = np.asarray(robot.home[target], dtype=float), None, []
    for move, sols in zip(moves, solutions, strict=True):
        at = f"{where} {move.name} ({target}, {arm.model})"
        joints, chosen = solve.nearest(arm, sols, q)
        if np.isnan(joints).any():
            raise ReachError(f"{at}: out of reach (no solution within the joint limits for the tool's flange)")
        if move.kind == "linear" and (int(chosen) != branch or np.max(np.abs(joints - q)) > 90.0):
            raise ReachError(f"{at}: the linear move would change the arm's configuration (a wrist or elbow flip)")
        out.append(joints)
        q, branch = joints, int(chosen)
    return out


def check_pallet(cell, pallet, target: str) -> PalletReach:
    """Every move of a full cycle for the target's arm with the cell's tool, from home: a joint move takes
    the solution nearest the joints before it (the controllers' rule where the program names no
    configuration), a linear move keeps the arm's configuration (its branch) and may not jump; each pose
    within the cell's joint and wrist margins. ReachError names pallet, target, box and pose."""
    robot = cell.robot
    arm = robot.arms[target]
    moves = full_cycle(cell, pallet)
    worst_joint, worst_wrist, worst = np.inf, np.inf, ""
    for move, joints in zip(moves, joints_of(cell, target, moves, f"pallet {pallet.name!r}"), strict=True):
        joint, wrist = margins(arm, joints)
        if joint < worst_joint:
            worst_joint, worst = joint, move.name
        worst_wrist = min(worst_wrist, wrist)
    need = robot.margins
    if worst_joint < need.joint_deg or worst_wrist < need.wrist_deg:
        raise ReachError(
            f"pallet {pallet.name!r} ({target}, {arm.model}): {worst_joint:.1f} deg to a joint limit ({worst}) and "
            f"the wrist {worst_wrist:.1f} deg from its singularity; the cell asks {need.joint_deg:g} and "
            f"{need.wrist_deg:g} deg"
        )
    return PalletReach(target, arm.model, pallet.name, len(moves), worst_joint, worst_wrist, worst)


def check(cell, only: list[str] | None = None) -> list[PalletReach]:
    if cell.robot is None:
        return []
    targets = [t for t in cell.targets if t in cell.robot.arms and (only is None or t in only)]
    return [check_pallet(cell, pallet, target) for target in targets for pallet in cell.pallets]
