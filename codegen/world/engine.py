"""Exact signed distances between the moving bodies and the cell's solids (and between the arm's own links), by the
coal collision library; a cheap bounding-sphere test orders the pairs so that only the near ones are measured."""

# coal (the maintained successor of HPP-FCL, itself a fork of FCL) computes signed distances between primitive
# shapes with its own GJK/EPA and closed forms for capsules, spheres and half-spaces: the distance is exact up to
# its solver's tolerance (about 1e-8 mm on the shapes here), negative where two shapes overlap (the depth).

from __future__ import annotations

from dataclasses import dataclass

import coal
import numpy as np

from codegen.robot.arms import Arm
from codegen.world.bodies import Body, arm_bodies, self_pairs
from codegen.world.solids import Box, Capsule, Cylinder, Floor, Solid, World


@dataclass(frozen=True)
class Nearest:
    """The least distance (mm, negative: overlap depth) at one configuration, between body and other (a solid's name
    or another body's name), and the two nearest points in the base frame (mm)."""

    distance: float
    body: str
    other: str
    point_body: tuple[float, float, float]
    point_other: tuple[float, float, float]


def _geometry(shape: Solid) -> tuple[coal.ShapeBase, np.ndarray]:
    """The coal shape and its pose in the shape's own frame (coal's capsules and cylinders are centred on z)."""
    if isinstance(shape, Box):
        return coal.Box(*map(float, shape.size)), np.eye(4)
    if isinstance(shape, Cylinder):
        return coal.Cylinder(float(shape.radius), float(shape.length)), np.eye(4)
    if isinstance(shape, Floor):
        return coal.Halfspace(np.array([0.0, 0.0, 1.0]), float(shape.height)), np.eye(4)
    a, b = np.asarray(shape.a, dtype=float), np.asarray(shape.b, dtype=float)
    length = float(np.linalg.norm(b - a))
    if length == 0.0:
        return coal.Sphere(float(shape.radius)), _at(a)
    return coal.Capsule(float(shape.radius), length), _z_along((b - a) / length, 0.5 * (a + b))


def _at(point: np.ndarray) -> np.ndarray:
    out = np.eye(4)
    out[:3, 3] = point
    return out


def _z_along(direction: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """A pose at centre whose z axis is direction (unit)."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(direction[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, direction)
    x /= np.linalg.norm(x)
    out = np.eye(4)
    out[:3, 0], out[:3, 1], out[:3, 2], out[:3, 3] = x, np.cross(direction, x), direction, centre
    return out


def _transform(pose: np.ndarray) -> coal.Transform3s:
    return coal.Transform3s(np.ascontiguousarray(pose[:3, :3]), np.ascontiguousarray(pose[:3, 3]))


def distance(one: Solid, one2base: np.ndarray, other: Solid, other2base: np.ndarray) -> tuple[float, np.ndarray, ...]:
    """The signed distance (mm) between two shapes placed at one2base . one.pose and other2base . other.pose, and the
    nearest points (base frame)."""
    g1, local1 = _geometry(one)
    g2, local2 = _geometry(other)
    result = coal.DistanceResult()
    d = coal.distance(
        g1, _transform(one2base @ one.pose @ local1), g2, _transform(other2base @ other.pose @ local2),
        coal.DistanceRequest(), result,
    )
    return float(d), np.array(result.getNearestPoint1()), np.array(result.getNearestPoint2())


class Cell:
    """An arm with its tool and carried part among the world's solids: least distances at given joint values."""

    def __init__(self, arm: Arm, world: World, tool=None, part=None, exempt: frozenset[tuple[str, str]] = frozenset(),
                 self_check: bool = True):
        """exempt: (body, solid) name pairs not measured (a part lying on the table it is placed on)."""
        self.arm = arm
        self.bodies: tuple[Body, ...] = arm_bodies(arm, tool, part)
        self.names = list(world.solids)
        self.solids = [world.solids[name] for name in self.names]
        self.pairs = self_pairs(arm, self.bodies) if self_check else ()
        self._body_geometry = [_geometry(body.shape) for body in self.bodies]
        self._solid_geometry = [(g, solid.pose @ local) for solid in self.solids for g, local in [_geometry(solid)]]
        self._frames = np.array([body.frame for body in self.bodies])
        self._body2frame = np.array([body.shape.pose for body in self.bodies])
        self._body_centre = np.array([_centre(body.shape) for body in self.bodies])[:, :3]
        self._body_radius = np.array([_radius(body.shape) for body in self.bodies])
        finite = [i for i, s in enumerate(self.solids) if not isinstance(s, Floor)]
        self._finite = np.array(finite, dtype=int)
        centres = [(self.solids[i].pose @ _centre(self.solids[i]))[:3] for i in finite]
        self._solid_centre = np.array(centres).reshape(-1, 3)
        self._solid_radius = np.array([_radius(self.solids[i]) for i in finite])
        self._floors = [i for i, s in enumerate(self.solids) if isinstance(s, Floor)]
        # the robot's base stands on its mounting plane and never moves: its capsule is not measured against a floor
        self._exempt = {(b, s) for b, s in exempt} | {
            (body.name, self.names[i]) for body in self.bodies if body.frame == 0 for i in self._floors
        }
        self.queries = 0  # exact distance queries made (for the benchmarks)

    def poses(self, joints_deg: np.ndarray) -> np.ndarray:
        """(n, bodies, 4, 4) body2base of (n, 6) joint values (deg)."""
        frames = self.arm.kin.link_frames(np.asarray(joints_deg, dtype=float).reshape(-1, 6))
        return frames[:, self._frames] @ self._body2frame

    def nearest(self, joints_deg: np.ndarray, below: float = np.inf) -> list[Nearest | None]:
        """Per configuration of (n, 6) joint values, the nearest pair (bodies to solids, and the checked pairs of
        bodies) if its distance is below `below` mm, else None."""
        poses, centres = self._placed(joints_deg)
        return [self._nearest_one(poses[n], centres[n], below) for n in range(len(poses))]

    def least(self, joints_deg: np.ndarray) -> tuple[int, Nearest | None]:
        """The sample of (n, 6) joint values with the least distance and its nearest pair: each sample measured only
        where nearer than the least found so far."""
        poses, centres = self._placed(joints_deg)
        best: Nearest | None = None
        where = 0
        for n in range(len(poses)):
            found = self._nearest_one(poses[n], centres[n], np.inf if best is None else best.distance)
            if found is not None:
                best, where = found, n
        return where, best

    def _placed(self, joints_deg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The bodies' poses (n, bodies, 4, 4) and bounding-sphere centres (n, bodies, 3) in the base frame."""
        poses = self.poses(joints_deg)
        centre = np.c_[self._body_centre, np.ones(len(self.bodies))]
        return poses, np.einsum("nbij,bj->nbi", poses[..., :3, :], centre)

    def _candidates(self, pose: np.ndarray, centre: np.ndarray) -> list[tuple[float, int, int, bool]]:
        """(lower bound of the distance, i, j, j is a body) for every pair: bounding spheres, a floor's plane."""
        out = []
        if len(self._finite):
            gap = np.linalg.norm(centre[:, None, :] - self._solid_centre[None], axis=-1)
            bound = gap - self._body_radius[:, None] - self._solid_radius[None]
            out += [(bound[b, k], b, int(s), False) for b in range(len(centre)) for k, s in enumerate(self._finite)]
        for s in self._floors:
            floor = self.solids[s]
            up = np.linalg.inv(floor.pose)[2]  # z in the floor's frame of a base-frame point
            heights = centre @ up[:3] + up[3] - floor.height
            out += [(heights[b] - self._body_radius[b], b, s, False) for b in range(len(centre))]
        if self.pairs:
            i, j = np.array(self.pairs).T
            bound = np.linalg.norm(centre[i] - centre[j], axis=-1) - self._body_radius[i] - self._body_radius[j]
            out += [(bound[k], int(i[k]), int(j[k]), True) for k in range(len(i))]
        return out

    def _nearest_one(self, pose: np.ndarray, centre: np.ndarray, below: float) -> Nearest | None:
        best: Nearest | None = None
        limit = below
        for bound, b, other, is_body in sorted(self._candidates(pose, centre), key=lambda c: c[0]):
            if bound >= limit:
                break
            one_name = self.bodies[b].name
            other_name = self.bodies[other].name if is_body else self.names[other]
            if not is_body and (one_name, other_name) in self._exempt:
                continue
            g1, local1 = self._body_geometry[b]
            if is_body:
                g2, local2 = self._body_geometry[other]
                other2base = pose[other] @ local2
            else:
                g2, other2base = self._solid_geometry[other]
            result = coal.DistanceResult()
            request = coal.DistanceRequest()
            d = coal.distance(g1, _transform(pose[b] @ local1), g2, _transform(other2base), request, result)
            self.queries += 1
            if d < limit:
                limit = d
                best = Nearest(float(d), one_name, other_name, tuple(result.getNearestPoint1()),
                               tuple(result.getNearestPoint2()))
        return best


def _centre(shape) -> np.ndarray:
    """The centre of a shape's bounding sphere in its own frame, homogeneous."""
    if isinstance(shape, Capsule):
        return np.r_[0.5 * (np.asarray(shape.a, dtype=float) + np.asarray(shape.b, dtype=float)), 1.0]
    return np.array([0.0, 0.0, 0.0, 1.0])


def _radius(shape) -> float:
    """The radius of a shape's bounding sphere about _centre (mm)."""
    if isinstance(shape, Capsule):
        return 0.5 * float(np.linalg.norm(np.subtract(shape.b, shape.a))) + shape.radius
    return shape.extent
