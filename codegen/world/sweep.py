"""Every move checked along its whole path by conservative advancement: from a sample at least distance d the next
may lie as far as the arm's travel bound allows while the move stays clear, and the least distance of the move with
the bodies and where."""

# The travel bound. Between two samples the joints change by dq (rad). A point on a body fixed in link frame f moves,
# by joint j alone, at most dist(point, axis j) |dq_j|, and dist(point, axis j) <= reach_j: the sum of the (fixed)
# distances between consecutive link-frame origins from frame j - 1 to frame f plus the body's extent about frame f's
# origin (every family's joint j axis passes through frame j - 1's or frame j's origin). So every point moves at most
# travel = sum_j reach_j |dq_j| between the two samples, if each joint moves monotonically between them (a joint move
# interpolates linearly; a linear move's joints are solved at samples this close). Two bodies move apart or together
# by no more than that either: in the lower body's link frame only the joints after it move the other.
#
# So the least distance m(t) of all pairs changes by no more than the travel between two instants, and between samples
# i and i + 1 (travel T), at travel x from sample i: m >= max(m_i - x, m_(i+1) - T + x) >= (m_i + m_(i+1) - T) / 2.
# The step. From sample i the next lies at travel T_i <= max(m_i - c, 0) + c / 2 (c the clearance). Where m_i >= c:
# m >= m_i - T_i >= c / 2 over the whole step, nothing can be touched; where m_i < c the sample is already a breach.
# So contact anywhere along a move (m <= 0, however thin the solid) always leaves a sample below the clearance, and a
# move passed (every sample >= c) keeps at least c / 2 everywhere; the reported lower bound is the least of
# (m_i + m_(i+1) - T_i) / 2 over the steps. A sample's m_i need only be known as far as it sets the step: pairs whose
# cheap bound is above what can matter (the step that reaches the move's end, or the least distance found so far)
# are not measured.

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from codegen import poses
from codegen.robot import solve
from codegen.robot.arms import Arm
from codegen.world.engine import GROUPS, Nearest, Scene

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


@dataclass(frozen=True, eq=False)
class JointPath:
    """A joint move (PTP, MoveJ, movej): every axis linear in s from start to end (deg)."""

    start: np.ndarray
    end: np.ndarray

    def __call__(self, s: float, _near: np.ndarray) -> np.ndarray:
        return self.start + s * (self.end - self.start)


def joint_path(q0, q1) -> JointPath:
    """A joint move (PTP, MoveJ, movej): every axis linear in s from q0 to q1 (deg)."""
    return JointPath(np.asarray(q0, dtype=float), np.asarray(q1, dtype=float))


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


def travel_weights(scene: Scene) -> np.ndarray:
    """(6,) mm per rad: the travel bound's weights (reach, per radian), computed once per scene."""
    weights = getattr(scene, "_travel_weights", None)
    if weights is None:
        weights = np.radians(reach(scene))
        scene._travel_weights = weights
    return weights


def group_weights(scene: Scene) -> np.ndarray:
    """(GROUPS, 6): per group of pairs the travel bound's weights of the joints that move its two sides against each
    other: every joint for the bodies against the solids (group 0), the joints after link frame g for the bodies'
    pairs whose lower frame is g (in that frame the lower body stands still)."""
    weights = travel_weights(scene)
    return np.array([np.where(np.arange(6) >= g, weights, 0.0) for g in range(GROUPS)])


def check_path(scene: Scene, path: Path, q_start, clearance_mm: float = CLEARANCE_MM, trail: list | None = None
               ) -> MoveClearance:
    """The least clearance along path (s from 0 to 1), starting at joints q_start (deg): a joint move, a linear move
    or a blend's corner (any Path: a corner gives its own joints along s). Samples by conservative advancement (the
    module's comment says why no contact slips between them); trail, if given, gets each sample's (s, joints, per
    group of pairs the least distance known there: exact, or a lower bound where nothing nearer could matter)."""
    if clearance_mm <= 0:
        raise ValueError("the clearance is a positive distance (mm)")
    weights = group_weights(scene)
    half = 0.5 * clearance_mm
    q_i = np.asarray(q_start, dtype=float)
    walk = _Grid(scene, path, q_i, weights, half) if isinstance(path, JointPath) else _Solved(scene, path, q_i, weights)
    s_i, pose_i = 0.0, walk.pose(0.0, q_i)
    best: Nearest | None = None
    best_s, best_q = 0.0, q_i
    lower = np.inf
    before: tuple[np.ndarray, np.ndarray] | None = None  # the sample before: its groups' known least, the step's travel
    samples = 0
    while True:
        rest = walk.rest(s_i, q_i)  # per group, the travel left (exact for a joint move, else an estimate)
        known, found = scene.least_by_group(pose_i, rest + half, np.inf if best is None else best.distance)
        samples += 1
        if trail is not None:
            trail.append((s_i, q_i, known))
        if found is not None and (best is None or found.distance < best.distance):
            best, best_s, best_q = found, s_i, q_i
        if before is not None:
            with np.errstate(invalid="ignore"):  # a group without pairs: inf - inf
                gap = 0.5 * (before[0] + known - before[1])
            lower = min(lower, float(np.nanmin(gap)))
        if s_i >= 1.0:
            break
        if samples >= MAX_SAMPLES:
            raise Unresolved(f"more than {MAX_SAMPLES} samples needed near {s_i:.4f} of the move")
        s_n, q_n, step, pose_i = walk.advance(s_i, q_i, np.maximum(known - clearance_mm, 0.0) + half, rest)
        before = (known, step)
        s_i, q_i = s_n, q_n
    if best is None:
        raise ValueError("the cell has nothing to measure (no solids and no checked pairs of links)")
    return MoveClearance(best.distance, min(lower, best.distance), best.body, best.other, best_s,
                         tuple(float(v) for v in best_q), best.point_body, samples)


class _Grid:
    """A joint move's samples on a fixed grid whose steps each travel at most half the clearance: the advance jumps
    to the farthest grid point every group's allowed travel reaches (the travel is linear in s), the bodies' poses
    computed for a block of grid points at once (one batched forward kinematics, not one per sample)."""

    BLOCK = 256

    def __init__(self, scene: Scene, path: JointPath, q0: np.ndarray, weights: np.ndarray, half: float):
        self.scene, self.q0 = scene, q0
        self.delta = path.end - q0
        self.total = weights @ np.abs(self.delta)  # per group
        self.count = max(1, int(np.ceil(self.total[0] / half)))  # grid intervals (group 0 travels the most)
        if self.count >= MAX_SAMPLES:
            raise Unresolved(f"more than {MAX_SAMPLES} samples needed for a joint move of {self.total[0]:.0f} mm")
        self.per_step = self.total / self.count
        self.index = 0
        self.block_start, self.block = -1, None

    def pose(self, s: float, q: np.ndarray) -> np.ndarray:
        return self._pose(0)

    def _pose(self, k: int) -> np.ndarray:
        if self.block is None or not self.block_start <= k < self.block_start + len(self.block):
            ks = np.arange(k, min(k + self.BLOCK, self.count + 1))
            self.block_start = k
            self.block = self.scene.poses(self.q0 + (ks / self.count)[:, None] * self.delta)
        return self.block[k - self.block_start]

    def rest(self, s: float, q: np.ndarray) -> np.ndarray:
        return self.total * (1.0 - s)

    def advance(self, s: float, q: np.ndarray, allowed: np.ndarray, rest: np.ndarray):
        moving = self.per_step > 0
        fits = np.floor(allowed[moving] / self.per_step[moving]).min() if moving.any() else self.count
        k = min(self.count, self.index + max(1, int(fits)))
        step = self.per_step * (k - self.index)
        self.index = k
        s_n = k / self.count
        return s_n, self.q0 + s_n * self.delta, step, self._pose(k)


class _Solved:
    """Any other path (a linear move, a blend's corner): each next sample solved from the one before, shortened until
    every group's travel bound fits what its distance allows."""

    def __init__(self, scene: Scene, path: Path, q0: np.ndarray, weights: np.ndarray):
        self.scene, self.path, self.weights = scene, path, weights
        self.end = path(1.0, q0)

    def pose(self, s: float, q: np.ndarray) -> np.ndarray:
        return self.scene.poses(q)[0]

    def rest(self, s: float, q: np.ndarray) -> np.ndarray:
        return self.weights @ np.abs(self.end - q)

    def advance(self, s: float, q: np.ndarray, allowed: np.ndarray, rest: np.ndarray):
        moving = rest > 0
        ratio = float((allowed[moving] / rest[moving]).min()) if moving.any() else 1.0
        ds = (1.0 - s) * min(1.0, ratio)
        for _ in range(200):
            s_n = min(1.0, s + ds)
            q_n = self.path(s_n, q)
            step = self.weights @ np.abs(q_n - q)
            over = step / allowed
            if over.max() <= 1.0:
                return s_n, q_n, step, self.pose(s_n, q_n)
            ds *= 0.9 / over.max()  # a curved path: shorter until the step's travel fits
        raise Unresolved(f"the move's joints cannot be followed near {s:.4f} of its length")
