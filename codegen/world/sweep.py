"""Every move checked along its whole path: samples close enough that no point of the arm, tool or part travels more
than half the clearance between two of them, and the least distance of the move with the bodies and where."""

# The step. Between two samples the joints change by dq (rad). A point on a body fixed in link frame f moves, by
# joint j alone, at most dist(point, axis j) |dq_j|, and dist(point, axis j) <= reach_j: the sum of the (fixed)
# distances between consecutive link-frame origins from frame j - 1 to frame f plus the body's extent about frame f's
# origin (every family's joint j axis passes through frame j - 1's or frame j's origin). So every point moves at most
# travel = sum_j reach_j |dq_j| between the two samples, if each joint moves monotonically between them (a joint move
# interpolates linearly; a linear move's joints are solved at samples this close). Samples are added until travel
# <= clearance / 2 for every neighbouring pair: then any instant is within clearance / 4 of a sample, the true least
# distance is at least the sampled least distance - clearance / 4 (MoveClearance.lower_bound), and a solid reached
# anywhere along the move (distance <= 0, however thin) shows at some sample as a distance below the clearance.

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from codegen import poses
from codegen.robot import solve
from codegen.robot.arms import Arm
from codegen.world.engine import Scene

CLEARANCE_MM = 20.0  # the cell's default clearance_mm (docs/clearance.md says why)
MAX_SAMPLES = 100_000  # a move that needs more (a joint swinging near a singularity) is reported unresolved

Path = Callable[[float, np.ndarray], np.ndarray]  # (s in [0, 1], the joints at the sample before) -> joints (deg)


@dataclass(frozen=True)
class MoveClearance:
    """The least distance of one move: measured at the samples (distance, mm), guaranteed along the whole move
    (lower_bound, mm), between body and other (a solid or a body), at fraction s of the move, at joints (deg)."""

    distance: float
    lower_bound: float
    body: str
    other: str
    s: float
    joints: tuple[float, ...]
    point: tuple[float, float, float]  # the body's nearest point, base frame (mm)
    samples: int

    def clear(self, clearance_mm: float) -> bool:
        return self.distance >= clearance_mm


class Unresolved(ValueError):
    """A path whose joints cannot be followed (no solution, or more than MAX_SAMPLES samples needed)."""


def reach(scene: Scene) -> np.ndarray:
    """(6,) reach_j (mm): a bound on any body point's distance from joint j's axis, whatever the joint values."""
    frames = scene.arm.kin.link_frames(np.zeros(6))
    origins = frames[:, :3, 3]
    link = np.linalg.norm(np.diff(origins, axis=0), axis=1)  # |o_(k+1) - o_k|, fixed by the link between them
    out = np.zeros(6)
    for body in scene.bodies:
        extent = _extent(body.shape)
        for j in range(1, body.frame + 1):  # joints 1 .. frame move the body
            out[j - 1] = max(out[j - 1], link[j - 1 : body.frame].sum() + extent)
    return out


def _extent(shape) -> float:
    """The farthest point of a shape from its link frame's origin (mm)."""
    centre = shape.pose[:3, 3]
    if hasattr(shape, "a"):  # a capsule: its segment's ends in the frame
        ends = [shape.pose[:3, :3] @ np.asarray(p, dtype=float) + centre for p in (shape.a, shape.b)]
        return float(max(np.linalg.norm(e) for e in ends)) + shape.radius
    return float(np.linalg.norm(centre)) + shape.extent


def joint_path(q0, q1) -> Path:
    """A joint move (PTP, MoveJ, movej): every axis linear in s from q0 to q1 (deg)."""
    start, end = np.asarray(q0, dtype=float), np.asarray(q1, dtype=float)
    return lambda s, _near: start + s * (end - start)


def linear_path(arm: Arm, tcp2flange: np.ndarray, tcp0: np.ndarray, tcp1: np.ndarray) -> Path:
    """A linear move (LIN, MoveL, movel) from tcp0 to tcp1 (tcp2base): the TCP on the straight line, its orientation
    turned about one fixed axis (the rotation from tcp0 to tcp1 scaled by s), the joints solved at each sample by the
    arm's IK, the solution nearest the sample before (as a controller continues a linear move)."""
    tcp0, tcp1 = np.asarray(tcp0, dtype=float), np.asarray(tcp1, dtype=float)
    turn = poses.rotvec_from_rotmat(tcp0[:3, :3].T @ tcp1[:3, :3])

    def at(s: float, near: np.ndarray) -> np.ndarray:
        pose = np.eye(4)
        pose[:3, :3] = tcp0[:3, :3] @ poses.rotmat_from_rotvec(s * np.asarray(turn))
        pose[:3, 3] = tcp0[:3, 3] + s * (tcp1[:3, 3] - tcp0[:3, 3])
        flange = solve.flange_poses(pose, tcp2flange)
        q, _ = solve.nearest(arm, solve.branches(arm, flange), near)
        if np.isnan(q).any():
            raise Unresolved(f"the linear move has no joint solution at {s:.4f} of its length")
        return q

    return at


def check_path(scene: Scene, path: Path, q_start, clearance_mm: float = CLEARANCE_MM) -> MoveClearance:
    """The least clearance along path (s from 0 to 1), starting at joints q_start (deg): a joint move, a linear move
    or a blend's corner (any Path: a corner gives its own joints along s)."""
    if clearance_mm <= 0:
        raise ValueError("the clearance is a positive distance (mm)")
    weights = np.radians(reach(scene))
    half = 0.5 * clearance_mm
    s = [0.0, 1.0]
    q = [np.asarray(q_start, dtype=float)]
    q.append(path(1.0, q[0]))
    worst = 0.0
    i = 0
    while i < len(s) - 1:  # bisect every interval whose travel bound exceeds half the clearance
        travel = float(weights @ np.abs(q[i + 1] - q[i]))
        if travel > half:
            if len(s) >= MAX_SAMPLES:
                raise Unresolved(f"more than {MAX_SAMPLES} samples needed near {s[i]:.4f} of the move")
            pieces = int(np.ceil(travel / half))
            middle = [s[i] + (s[i + 1] - s[i]) * k / pieces for k in range(1, pieces)]
            solved = []
            near = q[i]
            for value in middle:
                near = path(value, near)
                solved.append(near)
            s[i + 1 : i + 1] = middle
            q[i + 1 : i + 1] = solved
            continue  # measure the new first interval (a curved joint path may still exceed)
        worst = max(worst, travel)
        i += 1
    joints = np.array(q)
    where, best = scene.least(joints)
    if best is None:
        raise ValueError("the cell has nothing to measure (no solids and no checked pairs of links)")
    return MoveClearance(best.distance, best.distance - 0.5 * worst, best.body, best.other, s[where],
                         tuple(float(v) for v in joints[where]), best.point_body, len(s))
