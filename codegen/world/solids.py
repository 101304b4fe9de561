"""Solid shapes in a frame (mm), a World of named solids, and the tool's and carried part's shapes."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

_EYE = np.eye(4)
_EYE.flags.writeable = False


def _pose(pose) -> np.ndarray:
    """A rigid 4x4 pose as a read-only float array (identity if None)."""
    if pose is None:
        return _EYE
    out = np.array(pose, dtype=float)
    if out.shape != (4, 4) or not np.isfinite(out).all():
        raise ValueError("a pose is a finite 4x4 matrix")
    out.flags.writeable = False
    return out


def translation(x: float, y: float, z: float) -> np.ndarray:
    """The pose that moves by (x, y, z) mm without turning."""
    out = np.eye(4)
    out[:3, 3] = (x, y, z)
    return out


@dataclass(frozen=True, eq=False)
class Box:
    """A box of size (x, y, z) mm centred on its pose's origin, edges along the pose's axes."""

    size: tuple[float, float, float]
    pose: np.ndarray = field(default_factory=lambda: _EYE)

    def __post_init__(self):
        if len(self.size) != 3 or min(self.size) <= 0:
            raise ValueError("a box has three positive sizes")
        object.__setattr__(self, "pose", _pose(self.pose))

    @property
    def extent(self) -> float:
        """The radius of a sphere about the pose's origin that holds the shape (mm)."""
        return 0.5 * float(np.linalg.norm(self.size))


@dataclass(frozen=True, eq=False)
class Cylinder:
    """A cylinder of radius and length (mm) along its pose's z axis, centred on its pose's origin."""

    radius: float
    length: float
    pose: np.ndarray = field(default_factory=lambda: _EYE)

    def __post_init__(self):
        if self.radius <= 0 or self.length <= 0:
            raise ValueError("a cylinder has a positive radius and length")
        object.__setattr__(self, "pose", _pose(self.pose))

    @property
    def extent(self) -> float:
        return float(np.hypot(self.radius, 0.5 * self.length))


def shape_of(spec, moved: np.ndarray | None = None) -> Box | Cylinder:
    """A declared solid (codegen.model.world.SolidSpec) as a shape in the base frame, moved by `moved` (a base-frame
    motion: a station's reading; None: where declared)."""
    pose = spec.solid2base if moved is None else np.asarray(moved, dtype=float) @ spec.solid2base
    if spec.shape == "box":
        return Box(tuple(spec.size), pose)
    return Cylinder(spec.size[0], spec.size[1], pose)


def bounding_box(shape: Box | Cylinder) -> Box:
    """The box at the shape's pose that holds it (a cylinder's: 2 radius square across its axis)."""
    if isinstance(shape, Box):
        return shape
    return Box((2 * shape.radius, 2 * shape.radius, shape.length), shape.pose)


def separation_bound(a: Box, b: Box) -> float:
    """A lower bound on the distance between two boxes (mm; negative: a bound on how deep they overlap), from the
    separating axes (each box's three edges and their nine cross products): a projection shortens no distance, and
    the overlap along any axis is at least the depth the boxes must move apart."""
    rotation_a, rotation_b = a.pose[:3, :3], b.pose[:3, :3]
    half_a, half_b = 0.5 * np.asarray(a.size), 0.5 * np.asarray(b.size)
    centres = b.pose[:3, 3] - a.pose[:3, 3]
    axes = [*rotation_a.T, *rotation_b.T]
    for i in range(3):
        for j in range(3):
            axis = np.cross(rotation_a[:, i], rotation_b[:, j])
            norm = np.linalg.norm(axis)
            if norm > 1e-9:  # parallel edges: the faces' axes already cover that direction
                axes.append(axis / norm)
    axes = np.asarray(axes)
    reach_a = np.abs(axes @ rotation_a) @ half_a
    reach_b = np.abs(axes @ rotation_b) @ half_b
    return float(np.max(np.abs(axes @ centres) - reach_a - reach_b))


@dataclass(frozen=True, eq=False)
class Capsule:
    """The points within radius (mm) of the segment a-b (mm, in its pose's frame)."""

    radius: float
    a: tuple[float, float, float]
    b: tuple[float, float, float]
    pose: np.ndarray = field(default_factory=lambda: _EYE)

    def __post_init__(self):
        if self.radius <= 0:
            raise ValueError("a capsule has a positive radius")
        object.__setattr__(self, "pose", _pose(self.pose))

    @property
    def extent(self) -> float:
        return float(max(np.linalg.norm(self.a), np.linalg.norm(self.b))) + self.radius


@dataclass(frozen=True, eq=False)
class Floor:
    """Everything below the plane z = height (mm) of its pose's frame: the floor or the robot's mounting plane."""

    height: float = 0.0
    pose: np.ndarray = field(default_factory=lambda: _EYE)

    def __post_init__(self):
        object.__setattr__(self, "pose", _pose(self.pose))

    extent = float("inf")


Solid = Box | Cylinder | Capsule | Floor


@dataclass(frozen=True)
class World:
    """The cell's solids by name, in the robot's base frame (mm)."""

    solids: dict[str, Solid]

    def __post_init__(self):
        for name, solid in self.solids.items():
            if not isinstance(solid, Box | Cylinder | Capsule | Floor):
                raise TypeError(f"solid {name!r}: expected a Box, Cylinder, Capsule or Floor")


def tool_cylinder(tcp2flange: np.ndarray, radius: float) -> Cylinder:
    """The tool as a cylinder of radius (mm) from the flange's centre to the TCP, in the flange frame."""
    tcp = np.asarray(tcp2flange, dtype=float)[:3, 3]
    length = float(np.linalg.norm(tcp))
    if length <= 0:
        raise ValueError("a tool shape needs a TCP away from the flange")
    return Cylinder(radius, length, z_along(tcp / length, 0.5 * tcp))


def tool_box(size: tuple[float, float, float], tcp2flange: np.ndarray) -> Box:
    """The tool as a box of size (mm) along the flange-to-TCP line (z), its ends at the flange and the TCP's depth."""
    tcp = np.asarray(tcp2flange, dtype=float)[:3, 3]
    length = float(np.linalg.norm(tcp))
    if length <= 0:
        raise ValueError("a tool shape needs a TCP away from the flange")
    return Box((size[0], size[1], length), z_along(tcp / length, 0.5 * tcp))


def part_box(size: tuple[float, float, float], tcp2flange: np.ndarray, part2tcp: np.ndarray | None = None) -> Box:
    """A carried part as a box of size (mm) in the flange frame: gripped at the middle of its top face, which lies at
    the TCP, the box hanging along the TCP's z (the tool's approach direction), unless part2tcp (the box centre's
    pose in the TCP frame) says otherwise."""
    centre2tcp = translation(0.0, 0.0, 0.5 * size[2]) if part2tcp is None else np.asarray(part2tcp, dtype=float)
    return Box(tuple(size), np.asarray(tcp2flange, dtype=float) @ centre2tcp)


def z_along(direction: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """A pose at centre whose z axis is direction (a unit vector)."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(direction[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, direction)
    x /= np.linalg.norm(x)
    out = np.eye(4)
    out[:3, 0], out[:3, 1], out[:3, 2], out[:3, 3] = x, np.cross(direction, x), direction, centre
    return out
