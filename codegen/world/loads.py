"""Loads from shape: mass, centre of gravity and inertia of a solid box or cylinder about the flange, and the three
forms controllers take them in (principal axes as Z-Y-X angles, principal axes as a quaternion, the tensor at the
centre of gravity in flange axes; each target's TOML cites its manual for the form it uses)."""

# Lengths here are mm and inertias kg m2, as the controllers write them (1 kg mm2 = 1e-6 kg m2).

from __future__ import annotations

import struct
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from codegen import poses
from codegen.world.solids import tool_box, tool_cylinder

MM2_TO_M2 = 1e-6
# a run sets the same few loads over and over (every move records the load in force): so many of them remembered
REMEMBERED_LOADS = 256


@dataclass(frozen=True)
class Load:
    """A rigid load: mass (kg), centre of gravity in the flange frame (mm) and inertia tensor about the centre of
    gravity with axes along the flange's (kg m2)."""

    mass: float
    cog_mm: np.ndarray
    inertia_cog: np.ndarray

    def about_flange(self) -> np.ndarray:
        """The inertia tensor about the flange origin, flange axes (kg m2): the parallel-axis (Steiner) terms added,
        m (|d|^2 E - d d^T) with d the centre of gravity's offset."""
        d = self.cog_mm * 1e-3
        return self.inertia_cog + self.mass * (float(d @ d) * np.eye(3) - np.outer(d, d))

    def principal(self) -> tuple[np.ndarray, np.ndarray]:
        """The principal moments (kg m2) and the rotation whose columns are their axes (flange frame, right-handed),
        each axis the one nearest a flange axis and pointing its way: a load whose axes are the flange's keeps them
        (A = B = C = 0, aom the unit quaternion)."""
        moments, axes = np.linalg.eigh(self.inertia_cog)
        order = [int(k) for k in np.argsort(-np.abs(axes), axis=1)[:, 0]]  # flange axis k <- its nearest eigenvector
        if sorted(order) != [0, 1, 2]:
            order = [0, 1, 2]
        moments, axes = moments[order], axes[:, order]
        axes = axes * np.where(np.diag(axes) < 0, -1.0, 1.0)
        if np.linalg.det(axes) < 0:
            axes[:, 2] = -axes[:, 2]
        return moments, axes

    def principal_zyx(self) -> dict[str, float]:
        """Principal axes as Z-Y-X angles: M, CM (X, Y, Z mm; A, B, C deg of the principal axes), J (X, Y, Z kg m2)."""
        moments, axes = self.principal()
        a, b, c = poses.zyx_deg_from_rotmat(axes)
        x, y, z = (float(v) for v in self.cog_mm)
        jx, jy, jz = (float(v) for v in moments)
        return {"M": self.mass, "X": x, "Y": y, "Z": z, "A": a, "B": b, "C": c, "JX": jx, "JY": jy, "JZ": jz}

    def principal_quaternion(self) -> tuple[float, tuple[float, ...], tuple[float, ...], float, float, float]:
        """Principal axes as a quaternion: mass, cog (mm), the axes' orientation (q1..q4), the moments (kg m2)."""
        moments, axes = self.principal()
        aom = tuple(float(v) for v in poses.quat_from_rotmat(axes))
        return (self.mass, tuple(float(v) for v in self.cog_mm), aom, *(float(v) for v in moments))

    def tensor_at_cog(self) -> tuple[float, list[float], list[float]]:
        """The tensor at the centre of gravity: m, cog (m) and inertia [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] (kg m2, at
        the cog, flange axes). Ixy.. are written as the tensor's entries (minus the products of inertia); the
        manual does not say which sign it means (not confirmed; zero for a load whose axes are the flange's)."""
        i = self.inertia_cog
        tensor = [i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]]
        return self.mass, [float(v) * 1e-3 for v in self.cog_mm], [float(v) for v in tensor]

    def flat(self) -> tuple[float, ...]:
        """The load as the interpreters record it and verify compares it: mass (kg), centre of gravity (mm, flange
        frame), the tensor at the centre of gravity in flange axes (Ixx, Iyy, Izz, Ixy, Ixz, Iyz kg m2)."""
        i = self.inertia_cog
        values = (self.mass, *self.cog_mm, i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2])
        return tuple(float(v) for v in values)

    def moved(self, frame2flange: np.ndarray) -> Load:
        """The load given in another frame (a load in the tool frame) expressed in the flange frame."""
        pose = np.asarray(frame2flange, dtype=float)
        rotation = pose[:3, :3]
        return Load(self.mass, rotation @ self.cog_mm + pose[:3, 3], rotation @ self.inertia_cog @ rotation.T)

    def expressed_in(self, frame2flange: np.ndarray) -> Load:
        """The load (flange frame) expressed in another frame whose pose in the flange frame is frame2flange."""
        pose = np.asarray(frame2flange, dtype=float)
        rotation = pose[:3, :3].T
        return Load(self.mass, rotation @ (self.cog_mm - pose[:3, 3]), rotation @ self.inertia_cog @ rotation.T)


def point(mass: float, cog_mm) -> Load:
    """A point mass (no inertia about its centre of gravity): a load given without a shape."""
    return Load(float(mass), np.asarray(cog_mm, dtype=float).copy(), np.zeros((3, 3)))


def from_principal(mass: float, cog_mm, axes2frame: np.ndarray, moments) -> Load:
    """A load as the controllers write it: principal moments (kg m2) about axes whose orientation (columns) is
    axes2frame, at the centre of gravity cog_mm."""
    rotation = np.asarray(axes2frame, dtype=float)
    inertia = rotation @ np.diag([float(v) for v in moments]) @ rotation.T
    return Load(float(mass), np.asarray(cog_mm, dtype=float).copy(), inertia)


def from_tensor(mass: float, cog_mm, tensor) -> Load:
    """A load from the tensor at its centre of gravity as [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] (kg m2)."""
    xx, yy, zz, xy, xz, yz = (float(v) for v in tensor)
    inertia = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    return Load(float(mass), np.asarray(cog_mm, dtype=float).copy(), inertia)


def combined(*parts: Load) -> Load:
    """Loads carried together as one: the masses added, the common centre of gravity, and the tensor about it
    (each part's own about its centre plus its parallel-axis term from that centre to the common one)."""
    mass = sum(p.mass for p in parts)
    cog = sum(p.mass * p.cog_mm for p in parts) / mass
    inertia = np.zeros((3, 3))
    for p in parts:
        d = (p.cog_mm - cog) * 1e-3
        inertia = inertia + p.inertia_cog + p.mass * (float(d @ d) * np.eye(3) - np.outer(d, d))
    return Load(float(mass), cog, inertia)


def box(mass: float, size_mm, centre2flange: np.ndarray) -> Load:
    """A solid box of size (x, y, z) mm and mass (kg), centred and turned as centre2flange says."""
    x, y, z = (float(v) for v in size_mm)
    own = mass / 12.0 * np.diag([y * y + z * z, x * x + z * z, x * x + y * y]) * MM2_TO_M2
    return _placed(mass, own, centre2flange)


def cylinder(mass: float, radius_mm: float, length_mm: float, centre2flange: np.ndarray) -> Load:
    """A solid cylinder along its own z, centred and turned as centre2flange says."""
    r2, h2 = radius_mm * radius_mm, length_mm * length_mm
    side = mass * (3.0 * r2 + h2) / 12.0
    own = np.diag([side, side, mass * r2 / 2.0]) * MM2_TO_M2
    return _placed(mass, own, centre2flange)


def _placed(mass: float, own: np.ndarray, centre2flange: np.ndarray) -> Load:
    if not mass > 0:
        raise ValueError("a load has a positive mass")
    pose = np.asarray(centre2flange, dtype=float)
    rotation = pose[:3, :3]
    return Load(mass, pose[:3, 3].copy(), rotation @ own @ rotation.T)


def of_tool(tool, shaped: bool) -> Load:
    """The tool's load: its mass at its declared centre of gravity, with the inertia of its shape ([cell.tool]
    radius_mm: a solid cylinder, box_mm: a solid box, each from the flange to the TCP; codegen.world.solids) about
    that centre; a tool without a shape is a point mass there."""
    if not shaped:
        return point(tool.mass_kg, tool.cog_mm)
    if tool.box_mm is not None:
        shape = tool_box(tool.box_mm, tool.tcp2flange)
        own = box(tool.mass_kg, shape.size, shape.pose)
    else:
        shape = tool_cylinder(tool.tcp2flange, tool.radius_mm)
        own = cylinder(tool.mass_kg, shape.radius, shape.length, shape.pose)
    return Load(own.mass, np.asarray(tool.cog_mm, dtype=float), own.inertia_cog)


def with_tool(tool, shaped: bool, held: Load) -> Load:
    """The tool ([cell.tool], of_tool) and what it holds (a load in the TCP frame) as one load in the flange frame."""
    return combined(of_tool(tool, shaped), held.moved(tool.tcp2flange))


def held_box(mass: float, size_mm, centre2tcp: np.ndarray | None, tcp2flange: np.ndarray) -> Load:
    """A carried part in the flange frame: a solid box of size_mm whose centre and axes in the TCP frame are
    centre2tcp, or a point mass where the cell gives no size (centre2tcp: its translation is the centre of gravity)."""
    pose = np.asarray(tcp2flange, dtype=float) @ np.asarray(centre2tcp, dtype=float)
    return point(mass, pose[:3, 3]) if size_mm is None else box(mass, size_mm, pose)


class Remembered:
    """A pure function of numbers to a load's flat form (Load.flat), each result remembered by the numbers' exact
    bits: an interpreter records the load in force at every move from the same few values, and numpy on 3x3
    matrices costs tens of microseconds a time. Keyed by the bits, not by ==: 0.0 and -0.0 (equal, but a sign that
    reaches the result) stay apart, and a NaN is found again. At most REMEMBERED_LOADS results are kept."""

    def __init__(self, make: Callable[..., tuple[float, ...]]) -> None:
        self.make = make
        self.results: dict[bytes, tuple[float, ...]] = {}

    def __call__(self, *numbers: float) -> tuple[float, ...]:
        key = struct.pack(f"{len(numbers)}d", *numbers)
        result = self.results.get(key)
        if result is None:
            if len(self.results) >= REMEMBERED_LOADS:
                self.results.clear()
            result = self.results[key] = self.make(*numbers)
        return result
