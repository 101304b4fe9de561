"""Tool calibration from flange poses touching one fixed point: the TCP by least squares, its residuals, the
geometry of the pose set and the standard uncertainty the controllers' wizards do not report."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from codegen.csvfile import CsvError, number, read_rows
from codegen.generate import clears
from codegen.model.cell import CellError, load_cell, replace_cell_file
from codegen.poses import matrix_from_xyzabc, native_values, rotmat_from_zyx_deg, zyx_deg_from_rotmat
from codegen.robot.taught import ReachError
from codegen.writefile import WriteRefused

METHODS = {"tcp": (), "tcp-z": ("z",), "tcp-zx": ("z", "x")}  # the orientation rows each method needs
ROLES = ("point", "z", "x")
MIN_POINTS = 3
DUPLICATE_MM, DUPLICATE_DEG = 0.01, 0.01  # two touches closer than this are one touch
RANK_RELATIVE = 1e-3  # smallest / largest singular value of the system below this: rank-deficient
SAME_ORIENTATION_DEG = 0.1  # the z and x rows keep the orientation of the last point row
POSITION_LIMIT_MM = 10_000.0
ANGLE_LIMIT_DEG = 360.0  # as taught poses: a larger angle is the same turn, read with less precision


class ToolCalibrationError(Exception):
    """A pose file or pose set that cannot give a TCP; the message names file and line."""


@dataclass(frozen=True)
class ToolFit:
    tcp: tuple[float, float, float]  # flange frame, mm
    point: tuple[float, float, float]  # the fixed point, base frame, mm
    residuals_mm: tuple[float, ...]  # per point row
    uncertainty_mm: tuple[float, float, float]  # one standard uncertainty of each TCP coordinate
    smallest_singular_value: float  # of the least-squares system (unit rotations: 0 .. sqrt(2 n))
    orientation_spread_deg: float  # the largest rotation between two of the touches
    orientation: tuple[float, float, float] | None  # a, b, c (deg, R = Rz Ry Rx) of the tool in the flange
    method: str
    points: int

    @property
    def mean_mm(self) -> float:
        return float(np.mean(self.residuals_mm))

    @property
    def max_mm(self) -> float:
        return float(np.max(self.residuals_mm))

    def as_json(self) -> dict:
        return {
            "tcp": list(self.tcp),
            "point": list(self.point),
            "residuals_mm": list(self.residuals_mm),
            "mean_mm": self.mean_mm,
            "max_mm": self.max_mm,
            "uncertainty_mm": list(self.uncertainty_mm),
            "orientation": None if self.orientation is None else list(self.orientation),
            "method": self.method,
            "points": self.points,
            "smallest_singular_value": self.smallest_singular_value,
            "orientation_spread_deg": self.orientation_spread_deg,
        }


def read_poses(path: Path) -> list[tuple[int, str, np.ndarray]]:
    """(line, role, flange2base) per row of a CSV with header x,y,z,a,b,c[,role] (mm, deg, xyzabc)."""
    try:
        _header, rows = read_rows(path, (("x", "y", "z", "a", "b", "c"), ("x", "y", "z", "a", "b", "c", "role")))
    except CsvError as exc:
        raise ToolCalibrationError(str(exc)) from None
    out = []
    for row in rows:
        line = row.line
        try:
            values = [number(v) for v in row.cells[:6]]
        except ValueError:
            raise ToolCalibrationError(f"{path}:{line}: x..c must be numbers") from None
        if max(abs(v) for v in values[:3]) > POSITION_LIMIT_MM or max(abs(v) for v in values[3:]) > ANGLE_LIMIT_DEG:
            raise ToolCalibrationError(
                f"{path}:{line}: expected positions within +-10,000 mm and angles within +-360 deg"
            )
        role = row.cells[6].strip().lower() if len(row.cells) > 6 else "point"
        if role not in ROLES:
            raise ToolCalibrationError(f"{path}:{line}: role must be one of {', '.join(ROLES)}, got {role!r}")
        out.append((line, role, matrix_from_xyzabc(values)))
    return out


def _angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    cos = (np.trace(a[:3, :3].T @ b[:3, :3]) - 1.0) / 2.0
    return math.degrees(math.acos(max(-1.0, min(1.0, cos))))


def _angles_deg(rotations: np.ndarray) -> np.ndarray:
    """The rotation angle between every two of the rotations (n x n, deg): trace(Ra^T Rb) = 1 + 2 cos(angle)."""
    flat = rotations.reshape(len(rotations), 9)
    return np.degrees(np.arccos(np.clip((flat @ flat.T - 1.0) / 2.0, -1.0, 1.0)))


def fit(path: Path, rows: list[tuple[int, str, np.ndarray]], method: str = "tcp") -> ToolFit:
    """Least squares for R_i tcp + t_i = point over the point rows; the orientation rows after it."""
    points = [(line, pose) for line, role, pose in rows if role == "point"]
    extra = {role: (line, pose) for line, role, pose in rows if role != "point"}
    for role in ROLES[1:]:
        if sum(1 for _, r, _ in rows if r == role) > 1:
            raise ToolCalibrationError(f"{path}: more than one row with role {role}")
    if len(points) < MIN_POINTS:
        raise ToolCalibrationError(f"{path}: {len(points)} touches of the point; at least {MIN_POINTS} are needed")
    rotations = np.array([pose[:3, :3] for _, pose in points])
    translations = np.array([pose[:3, 3] for _, pose in points])
    apart_deg = _angles_deg(rotations)
    apart_mm = np.linalg.norm(translations[:, None, :] - translations[None, :, :], axis=2)
    same = np.tril((apart_mm < DUPLICATE_MM) & (apart_deg < DUPLICATE_DEG), k=-1)  # j < i: a later row repeats
    if same.any():
        i = int(np.argmax(same.any(axis=1)))
        j = int(np.argmax(same[i]))
        raise ToolCalibrationError(f"{path}:{points[i][0]}: the same pose as line {points[j][0]} (a duplicate touch)")
    n = len(points)
    system = np.concatenate([rotations, -np.broadcast_to(np.eye(3), (n, 3, 3))], axis=2).reshape(3 * n, 6)
    singular = np.linalg.svd(system, compute_uv=False)
    if singular[-1] < RANK_RELATIVE * singular[0]:
        raise ToolCalibrationError(
            f"{path}: the touches do not fix the TCP: their rotations are all about one axis (or too small to "
            f"tell apart; smallest singular value {singular[-1]:.2e}); tilt the tool about a second axis"
        )
    solution, *_ = np.linalg.lstsq(system, -translations.reshape(-1), rcond=None)
    tcp, point = solution[:3], solution[3:]
    errors = np.einsum("nij,j->ni", rotations, tcp) + translations - point  # (n, 3)
    residuals = np.linalg.norm(errors, axis=1)
    dof = 3 * n - 6
    sigma2 = float(np.sum(errors**2) / dof) if dof > 0 else float("nan")
    covariance = sigma2 * np.linalg.inv(system.T @ system)
    uncertainty = np.sqrt(np.diag(covariance)[:3])
    spread = float(apart_deg.max())
    missing = [role for role in METHODS[method] if role not in extra]
    if missing:
        raise ToolCalibrationError(f"{path}: method {method} needs a row with role {missing[0]}")
    orientation = _orientation(path, points[-1][1], extra, tcp, point, method) if METHODS[method] else None
    return ToolFit(
        tuple(float(v) for v in tcp),
        tuple(float(v) for v in point),
        tuple(float(v) for v in residuals),
        tuple(float(v) for v in uncertainty),
        float(singular[-1]),
        float(spread),
        orientation,
        method,
        n,
    )


def _orientation(path, reference: np.ndarray, extra: dict, tcp, point, method: str) -> tuple[float, float, float]:
    """The tool's axes: from the fixed point, the z row moved the TCP along the tool's +Z, the x row along
    its +X, both in the orientation of the last point row (the vendors' TCP & Z, X and 2-point methods)."""
    axes = {}
    for role in METHODS[method]:
        line, pose = extra[role]
        if _angle_deg(pose, reference) > SAME_ORIENTATION_DEG:
            raise ToolCalibrationError(f"{path}:{line}: the {role} row must keep the orientation of the last point row")
        moved = pose[:3, :3] @ tcp + pose[:3, 3] - point  # base frame
        if np.linalg.norm(moved) < 1.0:
            raise ToolCalibrationError(f"{path}:{line}: the {role} row moves the TCP less than 1 mm from the point")
        axes[role] = reference[:3, :3].T @ (moved / np.linalg.norm(moved))  # in the flange frame
    z = axes["z"]
    x = axes.get("x", np.array([1.0, 0.0, 0.0]))  # tcp-z: the flange's x, made square to z
    x = x - (x @ z) * z
    if np.linalg.norm(x) < 1e-6:
        raise ToolCalibrationError(f"{path}: the x direction is parallel to z")
    x /= np.linalg.norm(x)
    rotation = np.column_stack([x, np.cross(z, x), z])
    return tuple(float(v) for v in zyx_deg_from_rotmat(rotation))


def report_lines(result: ToolFit, max_uncertainty_mm: float) -> list[str]:
    tcp = ", ".join(f"{v:.3f}" for v in result.tcp)
    lines = [
        f"TCP in the flange frame: [{tcp}] mm ({result.method}, {result.points} touches)",
        "fixed point in the base frame: [" + ", ".join(f"{v:.3f}" for v in result.point) + "] mm",
        "residual per touch: " + ", ".join(f"{r:.4f}" for r in result.residuals_mm) + " mm",
        f"mean {result.mean_mm:.4f} mm, max {result.max_mm:.4f} mm (what the controllers' wizards show)",
        f"geometry: orientation spread {result.orientation_spread_deg:.1f} deg, smallest singular value "
        f"{result.smallest_singular_value:.3f}",
        "standard uncertainty of the TCP: " + ", ".join(f"{u:.4f}" for u in result.uncertainty_mm) + " mm (x, y, z)",
    ]
    if result.orientation is not None:
        abc = ", ".join(f"{v:.3f}" for v in result.orientation)
        lines.append(f"tool orientation in the flange frame: a, b, c = {abc} deg")
    if max(result.uncertainty_mm) > max_uncertainty_mm:
        lines.append(
            f"warning: an uncertainty is above {max_uncertainty_mm:g} mm: the touches are tilted too little from each "
            f"other ({result.orientation_spread_deg:.1f} deg) for their residuals; tilt them further (30-45 deg)"
        )
    return lines


_TOOL = re.compile(r"^\[cell\.tool\][^\n]*\n(?:(?!\[)[^\n]*(?:\n|$))*", re.MULTILINE)
_TCP_LINE = re.compile(r"^tcp\s*=[^\n]*$", re.MULTILINE)


def write_to_cell(cell_path: Path, result: ToolFit, source: str) -> None:
    """Set the tcp of the cell's [cell.tool] (in the cell's pose format), keeping the rest as written; the
    edited file must load and pass every kind's reach proof before it replaces the old one (its mode and a symlink
    kept)."""

    cell = load_cell(cell_path)
    orientation = result.orientation or tuple(zyx_deg_from_rotmat(_flange_orientation(cell)))
    values = native_values((*result.tcp, *orientation), "xyzabc", cell.pose_format)
    line = f"tcp = [{', '.join(f'{v:.6g}' for v in values)}]   # `codegen calibrate tcp` from {source}"

    def edit(text: str) -> str:
        match = _TOOL.search(text)
        if match is None or cell.robot is None:
            raise ToolCalibrationError(f"{cell_path}: no [cell.tool] table (with the tool's mass_kg and cog_mm) to set")
        body = match.group(0)
        if _TCP_LINE.search(body):
            body = _TCP_LINE.sub(lambda _m: line, body, count=1)
        else:
            body = body.rstrip("\n") + "\n" + line + "\n"
        return text[: match.start()] + body + text[match.end() :]

    try:
        # the arm must still take every pose of every kind with the new tool, and clear the solids
        replace_cell_file(cell_path, edit, prove=clears)
    except CellError as exc:
        raise ToolCalibrationError(f"{cell_path}: edited file would not load: {exc}") from None
    except ReachError as exc:
        raise ToolCalibrationError(f"{cell_path}: with this tool the cell would not generate: {exc}") from None
    except WriteRefused as exc:
        raise ToolCalibrationError(str(exc)) from None
    except OSError as exc:
        raise ToolCalibrationError(
            f"{cell_path}: cannot write: {exc.strerror or exc}; the file was left as it was"
        ) from None


def _flange_orientation(cell) -> np.ndarray:
    """The orientation the cell's tool has now (kept when the method measures only the TCP)."""
    return cell.robot.tool.tcp2flange[:3, :3] if cell.robot.tool_given else rotmat_from_zyx_deg(0.0, 0.0, 0.0)
