"""Loads from shape: mass, centre of gravity and inertia of a solid box or cylinder about the flange, and the three
forms controllers take them in (principal axes as Z-Y-X angles, principal axes as a quaternion, the tensor at the
centre of gravity in flange axes; each target's TOML cites its manual for the form it uses)."""

# Lengths here are mm and inertias kg m2, as the controllers write them (1 kg mm2 = 1e-6 kg m2).

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from codegen import poses

MM2_TO_M2 = 1e-6


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
