"""9-point hand-eye calibration (source 001 eq. 2): fit pixel -> robot mm by least squares."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from codegen.csvfile import CsvError, number, read_rows
from codegen.generate import clears
from codegen.kinds.station.section import image_angle_sign
from codegen.model.cell import CellError, read_cell_data, replace_cell_file
from codegen.robot.taught import ReachError
from codegen.writefile import WriteRefused

PIXEL_LIMIT = 100_000.0  # an image's pixel coordinates (the largest sensors are some 20,000 px wide)
POSITION_LIMIT_MM = 10_000.0  # robot positions, as the other calibrations take them
# The least spread of the points across their narrowest direction (RMS distance from the best line): a vision
# system's reading is good to some 0.1 px and a taught position to some 0.1 mm (an arm's repeatability), so a set
# narrower than ten times the one, or than the other, gives a scale set by that noise (assumed figures).
MIN_SPREAD = {"pixel": (1.0, "px"), "robot": (0.1, "mm")}


class HandEyeError(Exception):
    """A point file or point set that cannot give a calibration; the message names file and row."""


@dataclass(frozen=True)
class HandEyeFit:
    model: str  # "similarity" (rotation, per-axis scale, translation) or "affine"
    matrix: tuple[tuple[float, float, float], tuple[float, float, float]]  # [x y] = M [u v 1]
    rotation_deg: float | None
    scale_mm_per_px: tuple[float, float] | None
    translation_mm: tuple[float, float]
    residuals_mm: tuple[float, ...]
    points: int

    @property
    def max_residual_mm(self) -> float:
        return max(self.residuals_mm)

    @property
    def rms_residual_mm(self) -> float:
        return math.sqrt(sum(r * r for r in self.residuals_mm) / len(self.residuals_mm))

    def apply(self, u: float, v: float) -> tuple[float, float]:
        (a, b, c), (d, e, f) = self.matrix
        return a * u + b * v + c, d * u + e * v + f


def read_points(path: Path) -> np.ndarray:
    """Rows (u, v, x, y) from a CSV with header u,v,x,y; errors name the file and line."""
    try:
        _header, rows = read_rows(path, (("u", "v", "x", "y"),))
    except CsvError as exc:
        raise HandEyeError(str(exc)) from None
    points = []
    for row in rows:
        try:
            values = [number(cell) for cell in row.cells]
        except ValueError:
            raise HandEyeError(f"{path}:{row.line}: not a number in {','.join(row.cells)}") from None
        if max(abs(v) for v in values[:2]) > PIXEL_LIMIT or max(abs(v) for v in values[2:]) > POSITION_LIMIT_MM:
            raise HandEyeError(
                f"{path}:{row.line}: pixels must lie within +-{PIXEL_LIMIT:,.0f} px and robot positions within "
                f"+-{POSITION_LIMIT_MM:,.0f} mm"
            )
        points.append((row.line, *values))
    return np.array(points, dtype=float) if points else np.zeros((0, 5))


def check_points(points: np.ndarray, source: str) -> None:
    """Refuse sets that cannot determine the map: duplicates, too few, collinear."""
    seen: dict[tuple[float, float], int] = {}
    for line_no, u, v, _x, _y in points:
        key = (u, v)
        if key in seen:
            raise HandEyeError(f"{source}:{int(line_no)}: duplicate pixel point ({u:g}, {v:g}), also line {seen[key]}")
        seen[key] = int(line_no)
    if len(points) < 3:
        raise HandEyeError(f"{source}: {len(points)} distinct points; at least 3 non-collinear are needed (9 usual)")
    for columns, what in (((1, 2), "pixel"), ((3, 4), "robot")):
        xy = points[:, columns]
        centred = xy - xy.mean(axis=0)
        singular = np.linalg.svd(centred, compute_uv=False)
        if singular[1] <= 1e-9 * max(singular[0], 1e-12):
            raise HandEyeError(f"{source}: the {what} points are collinear; the map is not determined")
        width, least, unit = singular[1] / math.sqrt(len(points)), *MIN_SPREAD[what]
        if width < least:
            raise HandEyeError(
                f"{source}: the {what} points lie within {width:.3g} {unit} of a line (degenerate: at least {least:g} "
                f"{unit} across is needed, else the map's scale follows the points' noise); spread them over the image"
            )


def _affine(points: np.ndarray) -> np.ndarray:
    uv1 = np.column_stack([points[:, 1], points[:, 2], np.ones(len(points))])
    solution, *_ = np.linalg.lstsq(uv1, points[:, 3:5], rcond=None)
    return solution.T  # 2x3


def _similarity(points: np.ndarray, start: np.ndarray) -> np.ndarray:
    """Gauss-Newton on (theta, sx, sy, tx, ty) for [x y] = R(theta) diag(sx, sy) [u v] + t."""
    a = start[:, :2]
    theta = math.atan2(a[1, 0], a[0, 0])
    sx = math.hypot(a[0, 0], a[1, 0])
    sy = math.copysign(math.hypot(a[0, 1], a[1, 1]), np.linalg.det(a))
    params = np.array([theta, sx, sy, start[0, 2], start[1, 2]])
    u, v, xy = points[:, 1], points[:, 2], points[:, 3:5]
    for _ in range(50):
        theta, sx, sy, tx, ty = params
        c, s = math.cos(theta), math.sin(theta)
        model = np.column_stack([c * sx * u - s * sy * v + tx, s * sx * u + c * sy * v + ty])
        r = (model - xy).reshape(-1)
        jac = np.zeros((len(u) * 2, 5))
        jac[0::2, 0] = -s * sx * u - c * sy * v
        jac[1::2, 0] = c * sx * u - s * sy * v
        jac[0::2, 1], jac[1::2, 1] = c * u, s * u
        jac[0::2, 2], jac[1::2, 2] = -s * v, c * v
        jac[0::2, 3], jac[1::2, 4] = 1.0, 1.0
        step, *_ = np.linalg.lstsq(jac, -r, rcond=None)
        params = params + step
        if np.max(np.abs(step)) < 1e-13:
            break
    return params


def fit(points: np.ndarray, model: str = "similarity", source: str = "<points>") -> HandEyeFit:
    check_points(points, source)
    affine = _affine(points)
    if model == "affine":
        matrix = affine
        rotation, scale = None, None
    else:
        theta, sx, sy, tx, ty = _similarity(points, affine)
        if min(abs(sx), abs(sy)) < 1e-9:
            raise HandEyeError(f"{source}: fitted scale is zero; the points do not span the image")
        c, s = math.cos(theta), math.sin(theta)
        matrix = np.array([[c * sx, -s * sy, tx], [s * sx, c * sy, ty]])
        rotation = math.degrees(math.atan2(s, c))
        scale = (float(sx), float(sy))
    uv1 = np.column_stack([points[:, 1], points[:, 2], np.ones(len(points))])
    residuals = np.linalg.norm(uv1 @ matrix.T - points[:, 3:5], axis=1)
    if not (np.all(np.isfinite(matrix)) and np.all(np.isfinite(residuals))):
        raise HandEyeError(f"{source}: the fit does not converge to finite numbers; check the points' units")
    return HandEyeFit(
        model=model,
        matrix=tuple(tuple(float(v) for v in row) for row in matrix),
        rotation_deg=rotation,
        scale_mm_per_px=scale,
        translation_mm=(float(matrix[0, 2]), float(matrix[1, 2])),
        residuals_mm=tuple(float(r) for r in residuals),
        points=len(points),
    )


def toml_table(result: HandEyeFit, source: str) -> str:
    (a, b, c), (d, e, f) = result.matrix
    lines = [
        "[cell.camera.handeye]",
        f"# written by `codegen calibrate handeye` from {source}: [x, y] mm = pixel_to_mm . [u, v, 1]",
        f"# {result.points} points, max residual {result.max_residual_mm:.4f} mm, model {result.model}",
        f"pixel_to_mm = [[{a:.9g}, {b:.9g}, {c:.9g}], [{d:.9g}, {e:.9g}, {f:.9g}]]",
    ]
    return "\n".join(lines) + "\n"


def _table_pattern(name: str) -> re.Pattern:
    """A TOML table: its header line and every following line up to the next header."""
    return re.compile(rf"^\[{re.escape(name)}\][^\n]*\n(?:(?!\[)[^\n]*(?:\n|$))*", re.MULTILINE)


_TABLE = _table_pattern("cell.camera.handeye")
_ANGLE_SIGN = re.compile(r"^angle_sign\s*=\s*[-+]?\d+[^\n]*$", re.MULTILINE)


def _with_angle_sign(text: str, sign: int) -> str:
    """The [cell.camera] table's angle_sign set to what the fitted map's image imposes."""
    mirrored = "mirrored" if sign < 0 else "not mirrored"
    line = f"angle_sign = {sign:<22d}# set by `codegen calibrate handeye`: the image is {mirrored}"
    camera = _table_pattern("cell.camera").search(text)
    if camera is None:
        return text
    body = camera.group(0)
    body = _ANGLE_SIGN.sub(line, body, count=1) if _ANGLE_SIGN.search(body) else body.rstrip("\n") + "\n" + line + "\n"
    return text[: camera.start()] + body + text[camera.end() :]


def write_to_cell(cell_path: Path, result: HandEyeFit, source: str) -> None:
    """Replace (or add) the [cell.camera.handeye] table, keeping the rest of the file as written; the edited file
    must load and pass every kind's reach proof before it replaces the old one (its mode and a symlink kept)."""

    try:
        read_cell_data(cell_path)  # a cell file at all (a regular file within the size bound)
    except CellError as exc:
        raise HandEyeError(str(exc)) from None
    table = toml_table(result, source)

    def edit(text: str) -> str:
        if _TABLE.search(text):
            new = _TABLE.sub(lambda m: table + "\n", text, count=1)
        else:
            match = _table_pattern("cell.camera").search(text)
            if match is None:
                raise HandEyeError(f"{cell_path}: no [cell.camera] table to put the calibration after")
            new = text[: match.end()].rstrip("\n") + "\n\n" + table + "\n" + text[match.end() :]
        return _with_angle_sign(new, image_angle_sign(result.matrix))

    try:
        replace_cell_file(cell_path, edit, prove=clears)  # the edited file must still be a valid cell that generates
    except CellError as exc:
        raise HandEyeError(f"{cell_path}: edited file would not load: {exc}") from None
    except ReachError as exc:
        raise HandEyeError(f"{cell_path}: with this calibration the cell would not generate: {exc}") from None
    except WriteRefused as exc:
        raise HandEyeError(str(exc)) from None
    except OSError as exc:
        raise HandEyeError(f"{cell_path}: cannot write: {exc.strerror or exc}; the file was left as it was") from None
