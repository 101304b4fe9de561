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
from codegen.robot.kinematics import SMALL_BATCH
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


@dataclass(frozen=True, eq=False)
class LinearPath:
    """A linear move (LIN, MoveL, movel) from tcp0 to tcp1 (tcp2base): the TCP on the straight line, its orientation
    turned about one fixed axis (the rotation from tcp0 to tcp1 scaled by s), the joints solved at each sample by the
    arm's IK, the solution nearest the sample before (as a controller continues a linear move)."""

    arm: Arm
    tcp2flange: np.ndarray
    tcp0: np.ndarray
    tcp1: np.ndarray

    def poses(self, s: np.ndarray) -> np.ndarray:
        """(n, 4, 4) the TCP's poses at the fractions s (n,)."""
        s = np.asarray(s, dtype=float)
        turn = np.asarray(poses.rotvec_from_rotmat(self.tcp0[:3, :3].T @ self.tcp1[:3, :3]), dtype=float)
        angle = float(np.linalg.norm(turn))
        out = np.broadcast_to(np.eye(4), (len(s), 4, 4)).copy()
        if angle > 0.0:
            kx, ky, kz = turn / angle
            k = np.array([[0.0, -kz, ky], [kz, 0.0, -kx], [-ky, kx, 0.0]])
            a = s * angle
            turned = np.eye(3) + np.sin(a)[:, None, None] * k + (1.0 - np.cos(a))[:, None, None] * (k @ k)
        else:
            turned = np.broadcast_to(np.eye(3), (len(s), 3, 3))
        out[:, :3, :3] = self.tcp0[:3, :3] @ turned
        out[:, :3, 3] = self.tcp0[:3, 3] + s[:, None] * (self.tcp1[:3, 3] - self.tcp0[:3, 3])
        return out

    def __call__(self, s: float, near: np.ndarray) -> np.ndarray:
        return self.solve(np.array([s]), near)[0]

    def solve(self, s: np.ndarray, q0: np.ndarray) -> np.ndarray:
        """(n, 6) joints at the increasing fractions s, each the solution nearest the one before (the first nearest
        q0): solved in one batch, each pose's nearest to q0 kept where it is also the nearest to the pose before
        (then the chain gives the same), else followed one pose at a time from there."""
        return self.chain(s, self.branches(s), q0)

    def branches(self, s: np.ndarray, batched: bool | None = None) -> np.ndarray:
        """(n, 8, 6) the analytic solutions at the fractions s (batched: the kinematics' path, None by number)."""
        return self.arm.kin.ik(solve.flange_poses(self.poses(s), self.tcp2flange), batched)

    def chain(self, s: np.ndarray, solutions: np.ndarray, q0: np.ndarray) -> np.ndarray:
        """solve's choice among the solutions (n, 8, 6) at the fractions s."""
        q0 = np.asarray(q0, dtype=float)
        guess, _ = solve.nearest(self.arm, solutions, np.broadcast_to(q0, (len(s), 6)))
        chained, _ = solve.nearest(self.arm, solutions, np.vstack([q0[None], guess[:-1]]))
        same = np.all((chained == guess) | (np.isnan(chained) & np.isnan(guess)), axis=1)
        if not same.all():
            k = int(np.argmin(same))
            near = q0 if k == 0 else guess[k - 1]
            for i in range(k, len(s)):
                near, _ = solve.nearest(self.arm, solutions[i], near)
                guess[i] = near
        bad = np.isnan(guess).any(axis=1)
        if bad.any():
            raise Unresolved(f"the linear move has no joint solution at {s[int(np.argmax(bad))]:.4f} of its length")
        return guess


def linear_path(arm: Arm, tcp2flange: np.ndarray, tcp0: np.ndarray, tcp1: np.ndarray) -> LinearPath:
    """A linear move from tcp0 to tcp1 (LinearPath)."""
    return LinearPath(arm, np.asarray(tcp2flange, dtype=float), np.asarray(tcp0, dtype=float),
                      np.asarray(tcp1, dtype=float))


@dataclass(frozen=True, eq=False)
class CircularPath(LinearPath):
    """A circular move (CIRC, MoveC, movec) from tcp0 to tcp1 along its arc (a codegen.dialects.core.watch.Path
    through its via point: pose(s) at the share s of its length), the joints solved at each sample as a linear
    move's; the orientation the arc's own where it gives one (rotation(s): movec's modes), else turned from tcp0's
    to tcp1's as a linear move's."""

    arc: object = None

    def poses(self, s: np.ndarray) -> np.ndarray:
        out = super().poses(s)
        own = hasattr(self.arc, "rotation")
        for i, value in enumerate(np.asarray(s, dtype=float).tolist()):
            pose = self.arc.pose(value)
            out[i, :3, 3] = pose[:3, 3]
            if own:
                out[i, :3, :3] = pose[:3, :3]
        return out


def circular_path(arm: Arm, tcp2flange: np.ndarray, tcp0: np.ndarray, tcp1: np.ndarray, arc) -> CircularPath:
    """A circular move from tcp0 to tcp1 along arc (CircularPath)."""
    return CircularPath(arm, np.asarray(tcp2flange, dtype=float), np.asarray(tcp0, dtype=float),
                        np.asarray(tcp1, dtype=float), arc)


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
    walk = _Samples(scene, *_grid(path, q_i, weights[0], half), weights)
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


def _grid(path: Path, q0: np.ndarray, weights: np.ndarray, half: float) -> tuple[np.ndarray, np.ndarray]:
    """(s (n,), joints (n, 6)): samples of the path from s = 0 to 1 whose every step's travel bound (all joints) is
    at most half the clearance: a joint move's evenly spaced; any other path's solved, and the steps that travel
    farther cut into as many as they need, until none does."""
    if isinstance(path, JointPath):
        delta = path.end - q0
        count = max(1, int(np.ceil(float(weights @ np.abs(delta)) / half)))
        if count >= MAX_SAMPLES:
            raise Unresolved(f"more than {MAX_SAMPLES} samples needed for the joint move")
        s = np.linspace(0.0, 1.0, count + 1)
        return s, q0 + s[:, None] * delta
    solved = _Refined(path) if isinstance(path, LinearPath) else _one_by_one(path)
    end = path(1.0, q0)
    s = np.linspace(0.0, 1.0, max(1, int(np.ceil(float(weights @ np.abs(end - q0)) / half))) + 1)
    while True:
        q = solved(s, q0)
        travel = np.abs(np.diff(q, axis=0)) @ weights
        over = np.flatnonzero(travel > half)
        if not len(over):
            return s, q
        pieces = np.ceil(travel[over] / half).astype(int)
        cuts = zip(over.tolist(), pieces.tolist(), strict=True)
        added = [s[i] + (s[i + 1] - s[i]) * np.arange(1, n) / n for i, n in cuts]
        s = np.union1d(s, np.concatenate(added))
        if len(s) >= MAX_SAMPLES:
            raise Unresolved(f"more than {MAX_SAMPLES} samples needed near {s[over[0]]:.4f} of the move")


class _Refined:
    """solve(s, q0) of a linear or circular path over a grid that only gains samples: each sample's analytic
    solutions computed once (on the path the kinematics takes for the whole grid, so the numbers are those of
    path.solve(s, q0)), the choice among them made over the whole grid each time."""

    def __init__(self, path: LinearPath):
        self.path = path
        self.s: np.ndarray | None = None
        self.solutions: np.ndarray | None = None

    def __call__(self, s: np.ndarray, q0: np.ndarray) -> np.ndarray:
        batched = len(s) > SMALL_BATCH  # the kinematics' own choice for the whole grid
        if self.s is None or not batched or len(self.s) <= SMALL_BATCH:  # nothing solved the same way yet
            solutions = self.path.branches(s)
        else:
            known = np.isin(s, self.s)
            solutions = np.empty((len(s), *self.solutions.shape[1:]))
            solutions[known] = self.solutions[np.searchsorted(self.s, s[known])]
            solutions[~known] = self.path.branches(s[~known], batched=True)
        self.s, self.solutions = s, solutions
        return self.path.chain(s, solutions, q0)


def _one_by_one(path: Path):
    """solve(s, q0) of any path: each sample from the one before."""

    def solved(s: np.ndarray, q0: np.ndarray) -> np.ndarray:
        out, near = [], q0
        for value in s.tolist():
            near = path(value, near)
            out.append(near)
        return np.array(out)

    return solved


class _Samples:
    """A path's samples (each step traveling at most half the clearance): the advance jumps to the farthest sample
    every group's allowed travel reaches (the travel bounds of the steps between add up), the bodies' poses computed
    for a block of samples at once (one batched forward kinematics, not one per sample)."""

    BLOCK = 256

    def __init__(self, scene: Scene, s: np.ndarray, q: np.ndarray, weights: np.ndarray):
        self.scene, self.s, self.q = scene, s, q
        steps = np.abs(np.diff(q, axis=0)) @ weights.T  # (steps, groups)
        self.travelled = np.vstack([np.zeros(len(weights)), np.cumsum(steps, axis=0)])  # (samples, groups)
        self.columns = list(np.ascontiguousarray(self.travelled.T))  # per group, its travel up to each sample
        self.ends = self.travelled[-1].tolist()
        self.index = 0
        self.block_start, self.block = -1, None

    def pose(self, s: float, q: np.ndarray) -> np.ndarray:
        return self._pose(0)

    def _pose(self, k: int) -> np.ndarray:
        if self.block is None or not self.block_start <= k < self.block_start + len(self.block):
            self.block_start = k
            self.block = self.scene.poses(self.q[k : k + self.BLOCK])
        return self.block[k - self.block_start]

    def rest(self, s: float, q: np.ndarray) -> np.ndarray:
        return self.travelled[-1] - self.travelled[self.index]

    def advance(self, s: float, q: np.ndarray, allowed: np.ndarray, rest: np.ndarray):
        here = self.travelled[self.index]
        last = len(self.s) - 1
        k = last
        for g, limit in enumerate((here + allowed + 1e-9).tolist()):
            if limit < self.ends[g]:  # this group's allowed travel ends before the path's (inf: no pairs)
                k = min(k, int(self.columns[g].searchsorted(limit, side="right")) - 1)
        k = min(last, max(self.index + 1, k))
        step = self.travelled[k] - here
        self.index = k
        return float(self.s[k]), self.q[k], step, self._pose(k)
