"""Exact signed distances between the moving bodies and the cell's solids (and between the arm's own links), by the
coal collision library; a cheap bound (bounding spheres, a box's or cylinder's own signed distance) orders the pairs
so that only the near ones are measured."""

# coal (the maintained successor of HPP-FCL, itself a fork of FCL) computes signed distances between primitive
# shapes with its own GJK/EPA and closed forms for capsules, spheres and half-spaces: the distance is exact up to
# its solver's tolerance (about 1e-8 mm on the shapes here), negative where two shapes overlap (the depth).

from __future__ import annotations

import copy
from dataclasses import dataclass

import coal
import numpy as np

from codegen.robot.arms import Arm
from codegen.world.bodies import Body, arm_bodies, self_pairs
from codegen.world.solids import Box, Capsule, Cylinder, Floor, Solid, World, z_along


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
    return coal.Capsule(float(shape.radius), length), z_along((b - a) / length, 0.5 * (a + b))


def _at(point: np.ndarray) -> np.ndarray:
    out = np.eye(4)
    out[:3, 3] = point
    return out


def _transform(pose: np.ndarray) -> coal.Transform3s:
    return coal.Transform3s(np.ascontiguousarray(pose[:3, :3]), np.ascontiguousarray(pose[:3, 3]))


def distance(
    one: Solid, one2base: np.ndarray, other: Solid, other2base: np.ndarray
) -> tuple[float, np.ndarray, np.ndarray]:
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


GROUPS = 7  # pair groups: 0 the bodies against the solids, 1 .. 6 the bodies' pairs by their lower link frame


class Scene:
    """An arm with its tool and carried part among the world's solids: least distances at given joint values."""

    def __init__(self, arm: Arm, world: World, tool=None, part=None, exempt: frozenset[tuple[str, str]] = frozenset(),
                 self_check: bool = True):
        """exempt: (body, solid) name pairs not measured (a part lying on the table it is placed on)."""
        self.arm = arm
        self.bodies: tuple[Body, ...] = arm_bodies(arm, tool, part)
        self.names = list(world.solids)
        self.solids = [world.solids[name] for name in self.names]
        self.pairs = self_pairs(arm, self.bodies) if self_check else ()
        geometry = [_geometry(body.shape) for body in self.bodies]
        self._body_shape = [g for g, _ in geometry]
        # body2frame . the coal shape's own pose: the origin of each is its bounding sphere's centre
        placed = zip(self.bodies, geometry, strict=True)
        self._body2frame = np.array([body.shape.pose @ local for body, (_, local) in placed])
        self._frames = np.array([body.frame for body in self.bodies])
        self._body_radius = np.array([_radius(body.shape) for body in self.bodies])
        self._solid_shape, self._solid_transform, centres = [], [], []
        for solid in self.solids:
            g, local = _geometry(solid)
            self._solid_shape.append(g)
            self._solid_transform.append(_transform(solid.pose @ local))
            centres.append((solid.pose @ local)[:3, 3])
        self._solid_centre = np.array(centres).reshape(-1, 3)
        self._solid_radius = np.array([_radius(solid) for solid in self.solids])
        # boxes and cylinders bound by their own signed distance from a body's bounding sphere (tighter than
        # their bounding spheres): per kind, the solids' indices, base2solid and their half sizes
        self._fitted = [_Fitted(self.solids, kind) for kind in (Box, Cylinder)]
        floors = [i for i, solid in enumerate(self.solids) if isinstance(solid, Floor)]
        self._floor_up = {i: np.linalg.inv(self.solids[i].pose)[2] for i in floors}  # a point's height in its frame
        # the robot's base stands on its mounting plane and never moves: its capsule is not measured against a floor
        skip = {(b, s) for b, s in exempt} | {(body.name, self.names[i]) for body in self.bodies
                                             if body.frame == 0 for i in floors}
        index = {name: i for i, name in enumerate(self.names)}
        self._skip = np.zeros((len(self.bodies), len(self.solids)), dtype=bool)
        for b, body in enumerate(self.bodies):
            for one, other in skip:
                if one == body.name and other in index:
                    self._skip[b, index[other]] = True
        pairs = np.array(self.pairs, dtype=int).reshape(-1, 2)
        self._pair_i, self._pair_j = pairs[:, 0], pairs[:, 1]
        # each pair's group: 0 for a body and a solid (every joint moves them apart), else the lower link frame of
        # the two bodies (only the joints after it move one against the other)
        frames = np.array([body.frame for body in self.bodies], dtype=int)
        self._group = np.concatenate([np.zeros(self._skip.size, dtype=int),
                                      np.minimum(frames[self._pair_i], frames[self._pair_j])])
        self._present = np.bincount(self._group, minlength=GROUPS)[:GROUPS] > 0
        self._skip_all = np.concatenate([self._skip.ravel(), np.zeros(len(self._pair_i), dtype=bool)])
        self._group_list = self._group.tolist()
        self._pair_i_list, self._pair_j_list = self._pair_i.tolist(), self._pair_j.tolist()
        self._placed = [coal.Transform3s() for _ in self.bodies]  # each body's coal transform at a pose
        self._one, self._other = coal.Transform3s(), coal.Transform3s()
        self._request, self._result = coal.DistanceRequest(), coal.DistanceResult()
        self.queries = 0  # exact distance queries made (for the benchmarks)

    def excluding(self, pairs: frozenset[tuple[str, str]]) -> Scene:
        """The same scene with these (body, solid) name pairs not measured as well."""
        out = copy.copy(self)
        out._skip = self._skip.copy()
        index = {name: i for i, name in enumerate(self.names)}
        for b, body in enumerate(self.bodies):
            for one, other in pairs:
                if one == body.name and other in index:
                    out._skip[b, index[other]] = True
        out._skip_all = np.concatenate([out._skip.ravel(), self._skip_all[self._skip.size:]])
        return out

    def within(self, joints_deg: np.ndarray, bodies: tuple[str, ...], limit: float) -> frozenset[tuple[str, str]]:
        """The (body, solid) name pairs of the named bodies nearer than limit (mm) at one configuration (every such
        pair measured, the pairs not measured left out)."""
        poses = self.poses(joints_deg)[0]
        out = set()
        for b, body in enumerate(self.bodies):
            if body.name not in bodies:
                continue
            for s, name in enumerate(self.names):
                if self._skip[b, s]:
                    continue
                self._one.setTransform(np.ascontiguousarray(poses[b, :3, :3]), np.ascontiguousarray(poses[b, :3, 3]))
                self._result.clear()
                d = coal.distance(self._body_shape[b], self._one, self._solid_shape[s], self._solid_transform[s],
                                  self._request, self._result)
                if d < limit:
                    out.add((body.name, name))
        return frozenset(out)

    def poses(self, joints_deg: np.ndarray) -> np.ndarray:
        """(n, bodies, 4, 4): each body's coal pose in the base frame (its origin the bounding sphere's centre)."""
        frames = self.arm.kin.link_frames(np.asarray(joints_deg, dtype=float).reshape(-1, 6))
        return frames[:, self._frames] @ self._body2frame

    def nearest(self, joints_deg: np.ndarray, below: float = np.inf) -> list[Nearest | None]:
        """Per configuration of (n, 6) joint values, the nearest pair (bodies to solids, and the checked pairs of
        bodies) if its distance is below `below` mm, else None."""
        poses = self.poses(joints_deg)
        return [self._nearest_one(poses[n], below) for n in range(len(poses))]

    def nearest_at(self, joints_deg: np.ndarray, below: float = np.inf) -> Nearest | None:
        """The nearest pair at one configuration (6,) if its distance is below `below` mm, else None (every pair is
        then at least `below` apart): only the pairs whose bound is below the least found so far are measured."""
        return self._nearest_one(self.poses(joints_deg)[0], below)

    def nearest_pose(self, poses: np.ndarray, below: float = np.inf) -> Nearest | None:
        """nearest_at for the bodies' poses (bodies, 4, 4) as `poses` gives them."""
        return self._nearest_one(poses, below)

    def least_by_group(self, pose: np.ndarray, caps: np.ndarray, below: float) -> tuple[np.ndarray, Nearest | None]:
        """At the bodies' poses (bodies, 4, 4): per group of pairs (self._group: 0 the bodies against the solids,
        g > 0 the bodies' pairs whose lower link frame is g) a lower bound of its least distance, exact where it is
        below caps[g]; and the nearest pair of all if nearer than `below` (else None). Only the pairs whose cheap
        bound is below what can still matter (their group's cap and least so far, or the nearest so far) are
        measured: an unmeasured pair is at least its bound away, and its bound at least min(cap, least)."""
        bounds, skip = self._bounds(pose[:, :3, 3])
        caps = np.asarray(caps, dtype=float)
        stop = max(float(caps.max()), below)
        # the pairs in reach of `stop`, in the order of their bounds (a stable sort of them: the order of all)
        near = np.flatnonzero((bounds < stop) & ~skip)
        least = [np.inf] * GROUPS
        best: Nearest | None = None
        if len(near):
            near = near[np.argsort(bounds[near], kind="stable")]
            best = self._measure(pose, near.tolist(), bounds[near].tolist(), caps.tolist(), least, below)
        return np.where(self._present, np.minimum(least, caps), np.inf), best

    def _measure(self, pose: np.ndarray, pairs: list[int], bounds: list[float], caps: list[float],
                 least: list[float], limit: float) -> Nearest | None:
        """least_by_group's measuring: the pairs (indices in _bounds' layout, by increasing bound) measured while
        their bound is below their group's cap and least so far or the nearest so far (`limit`); least updated
        per group, the nearest below `limit` returned. Each body placed once (its coal transform)."""
        group, pair_i, pair_j = self._group_list, self._pair_i_list, self._pair_j_list
        solid_pairs, count = self._skip.size, len(self.solids)
        rotations = np.ascontiguousarray(pose[:, :3, :3])
        origins = np.ascontiguousarray(pose[:, :3, 3])
        placed = self._placed
        ready = [False] * len(placed)
        request, result, distance = self._request, self._result, coal.distance
        best: Nearest | None = None
        for k, bound in zip(pairs, bounds, strict=True):
            g = group[k]
            if bound >= limit and (bound >= caps[g] or bound >= least[g]):
                continue
            if k < solid_pairs:
                b, s = divmod(k, count)
                other_shape, other_name, other = self._solid_shape[s], self.names[s], self._solid_transform[s]
            else:
                b, j = pair_i[k - solid_pairs], pair_j[k - solid_pairs]
                other_shape, other_name, other = self._body_shape[j], self.bodies[j].name, placed[j]
                if not ready[j]:
                    other.setTransform(rotations[j], origins[j])
                    ready[j] = True
            if not ready[b]:
                placed[b].setTransform(rotations[b], origins[b])
                ready[b] = True
            result.clear()
            d = distance(self._body_shape[b], placed[b], other_shape, other, request, result)
            self.queries += 1
            if d < least[g]:
                least[g] = d
            if d < limit:
                limit = d
                best = Nearest(float(d), self.bodies[b].name, other_name, tuple(result.getNearestPoint1()),
                               tuple(result.getNearestPoint2()))
        return best

    def least(self, joints_deg: np.ndarray) -> tuple[int, Nearest | None]:
        """The sample of (n, 6) joint values with the least distance and its nearest pair. The samples are taken in
        the order of their least lower bound, and measured only while that bound is below the least distance found
        so far (the bound is a true lower bound: no sample left out can be nearer)."""
        poses = self.poses(joints_deg)
        bounds, skip = self._bounds(poses[..., :3, 3])
        floor = np.where(skip, np.inf, bounds).min(axis=-1)
        best: Nearest | None = None
        where = 0
        for n in np.argsort(floor, kind="stable").tolist():
            limit = np.inf if best is None else best.distance
            if floor[n] >= limit:
                break
            found = self._nearest_one(poses[n], limit, (bounds[n], skip))
            if found is not None:
                best, where = found, n
        return where, best

    def _bounds(self, centre: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Lower bounds of every pair's signed distance for the bodies' centres (..., bodies, 3), flat on the last
        axis: body-solid pairs (bodies x solids, row-major), then the checked body pairs; and the skip mask of that
        layout. A body is within its bounding sphere; a box's or cylinder's bound is the sphere's centre's signed
        distance to it less the sphere's radius (inside it, no deeper than that: moved out along the nearest face
        by the depth and the radius, the sphere is clear), a floor's the centre's height above it less the radius,
        any other pair's the two bounding spheres' gap."""
        lead = centre.shape[:-2]
        radius = self._body_radius
        gap = np.sqrt(np.square(centre[..., :, None, :] - self._solid_centre).sum(axis=-1))
        solid_bound = gap - radius[:, None] - self._solid_radius
        for fitted in self._fitted:
            if fitted.index:
                solid_bound[..., fitted.index] = fitted.signed(centre) - radius[:, None]
        for s, up in self._floor_up.items():
            solid_bound[..., s] = centre @ up[:3] + up[3] - self.solids[s].height - radius
        between = centre[..., self._pair_i, :] - centre[..., self._pair_j, :]
        pair_bound = np.sqrt(np.square(between).sum(axis=-1)) - radius[self._pair_i] - radius[self._pair_j]
        bounds = np.concatenate([solid_bound.reshape(*lead, -1), pair_bound], axis=-1)
        return bounds, self._skip_all

    def _nearest_one(self, pose: np.ndarray, below: float, bounded=None) -> Nearest | None:
        bounds, skip = self._bounds(pose[:, :3, 3]) if bounded is None else bounded
        order = np.argsort(bounds, kind="stable")
        solid_pairs = self._skip.size
        count = len(self.solids)
        best: Nearest | None = None
        limit = below
        for k in order.tolist():
            if bounds[k] >= limit:
                break
            if skip[k]:
                continue
            if k < solid_pairs:
                b, s = divmod(k, count)
                other_shape, other_name = self._solid_shape[s], self.names[s]
                other = self._solid_transform[s]
            else:
                b, j = int(self._pair_i[k - solid_pairs]), int(self._pair_j[k - solid_pairs])
                other_shape, other_name = self._body_shape[j], self.bodies[j].name
                other = self._other
                other.setTransform(np.ascontiguousarray(pose[j, :3, :3]), np.ascontiguousarray(pose[j, :3, 3]))
            self._one.setTransform(np.ascontiguousarray(pose[b, :3, :3]), np.ascontiguousarray(pose[b, :3, 3]))
            self._result.clear()
            d = coal.distance(self._body_shape[b], self._one, other_shape, other, self._request, self._result)
            self.queries += 1
            if d < limit:
                limit = d
                best = Nearest(float(d), self.bodies[b].name, other_name, tuple(self._result.getNearestPoint1()),
                               tuple(self._result.getNearestPoint2()))
        return best


class _Fitted:
    """The solids of one kind (Box or Cylinder) for _bounds: a point's signed distance to each (mm)."""

    def __init__(self, solids: list, kind: type):
        self.index = [i for i, solid in enumerate(solids) if type(solid) is kind]
        inverse = [np.linalg.inv(solids[i].pose) for i in self.index]
        self.rotation = np.array([m[:3, :3].T for m in inverse]).reshape(-1, 3, 3)  # solid2base's rotation
        self.origin = np.array([solids[i].pose[:3, 3] for i in self.index]).reshape(-1, 3)
        if kind is Box:
            self.half = np.array([np.asarray(solids[i].size, dtype=float) / 2 for i in self.index]).reshape(-1, 3)
        else:
            self.half = np.array([(solids[i].radius, solids[i].length / 2) for i in self.index]).reshape(-1, 2)

    def signed(self, point: np.ndarray) -> np.ndarray:
        """(..., points, 3) in the base frame -> (..., points, solids): the signed distance (negative inside)."""
        local = np.abs(np.einsum("...psj,sjk->...psk", point[..., :, None, :] - self.origin, self.rotation))
        if self.half.shape[-1] == 2:  # a cylinder along its z: radial and axial
            local = np.stack([np.hypot(local[..., 0], local[..., 1]), local[..., 2]], axis=-1)
        over = local - self.half
        outside = np.sqrt(np.square(np.maximum(over, 0.0)).sum(axis=-1))
        return outside + np.minimum(over.max(axis=-1), 0.0)


def _radius(shape) -> float:
    """The radius of a shape's bounding sphere about the origin of its coal pose (mm)."""
    if isinstance(shape, Capsule):
        return 0.5 * float(np.linalg.norm(np.subtract(shape.b, shape.a))) + shape.radius
    return shape.extent
