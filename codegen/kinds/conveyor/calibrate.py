"""`codegen calibrate conveyor`: encoder scale, belt frame and camera offset from touched points (source 002)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import pairwise
from pathlib import Path

import numpy as np

from codegen.csvfile import CsvError, number, read_rows, whole
from codegen.generate import clears
from codegen.kinds.conveyor.section import belt2base, conveyor_of
from codegen.model.cell import CellError, load_cell, read_cell_data, replace_cell_file
from codegen.robot.taught import ReachError
from codegen.writefile import WriteRefused

ROLES = ("belt", "side")
MIN_TOUCHES = 2
SPAN_SHARE = 0.5  # source 002: the touches span at least half (better three quarters) of the working length
MAX_RESIDUAL_MM = 0.5  # a touch further than this from the fitted line: a slipped cone or a misread count
POSITION_LIMIT_MM = 10_000.0
COUNT_MIN, COUNT_MAX = -(2**63), 2**64 - 1  # a counter value: signed or unsigned, at most 64 bits
MIN_SPAN_MM = 10.0  # touches closer than this along the belt: no direction and no scale
# the robot's own decoder (UR): encoder_get_tick_count(0) returns the filtered count, a whole number in [0; 65536[
# (URScript Script Directory e-Series, module motion); its steps between touches unwound as the PLC's counts are
TICK_BITS = 16
TICK_SCALE_TOL = 1e-3  # ticks per PLC count further than this from +-1: the two count at different scales (said)


class ConveyorCalibrationError(ValueError):
    pass


@dataclass(frozen=True)
class Touch:
    line: int
    role: str
    position: np.ndarray  # base frame, mm
    count: int  # raw encoder count
    ticks: int | None = None  # the robot's own decoder's tick count at the touch (encoder_get_tick_count), if read


HEADERS = (
    ("x", "y", "z", "count"),
    ("x", "y", "z", "count", "role"),
    ("x", "y", "z", "count", "ticks"),
    ("x", "y", "z", "count", "role", "ticks"),
)


def read_touches(path: Path) -> list[Touch]:
    """Rows of a CSV with header x,y,z,count[,role][,ticks] (mm in the base frame, the raw counter value, the
    robot's own tick count), in the order the cone was touched as the belt carried it (upstream first). A side
    point may leave its ticks empty."""
    try:
        header, rows = read_rows(path, HEADERS)
    except CsvError as exc:
        raise ConveyorCalibrationError(str(exc)) from None
    column = dict(zip(header, range(len(header)), strict=True))
    out = []
    for row in rows:
        line = row.line
        try:
            position = [number(v) for v in row.cells[:3]]
            count = whole(row.cells[3])
        except ValueError:
            raise ConveyorCalibrationError(f"{path}:{line}: x, y, z must be numbers and count a whole number") from None
        if not all(abs(v) <= POSITION_LIMIT_MM for v in position):
            raise ConveyorCalibrationError(f"{path}:{line}: positions must be finite, within +-10,000 mm")
        if not COUNT_MIN <= count <= COUNT_MAX:
            raise ConveyorCalibrationError(f"{path}:{line}: count out of range")
        role = row.cells[column["role"]].strip().lower() if "role" in column else "belt"
        if role not in ROLES:
            raise ConveyorCalibrationError(f"{path}:{line}: role must be belt or side, got {role!r}")
        ticks = _ticks(path, line, row.cells[column["ticks"]], role) if "ticks" in column else None
        out.append(Touch(line, role, np.array(position), count, ticks))
    return out


def _ticks(path: Path, line: int, text: str, role: str) -> int | None:
    """A tick count as encoder_get_tick_count(0) returns it: a whole number 0 .. 65535 (empty: a side point)."""
    if not text.strip() and role == "side":
        return None
    try:
        value = number(text)
    except ValueError:
        value = math.nan
    ticks = int(value) if math.isfinite(value) and value == int(value) else None  # the filtered count is a float
    if ticks is None or not 0 <= ticks < 2**TICK_BITS:
        raise ConveyorCalibrationError(
            f"{path}:{line}: ticks must be the robot's encoder_get_tick_count(0), a whole number 0 to "
            f"{2**TICK_BITS - 1}, got {text.strip()!r}"
        )
    return ticks


def unwrap(counts: list[int], bits: int) -> np.ndarray:
    """Counts relative to the first, unwrapped across the counter's rollover: each step between two
    touches is taken as the shortest way round a counter of 2**bits values (the belt moves less than
    half the counter's range between touches)."""
    span = 2**bits
    steps = [((b - a + span // 2) % span) - span // 2 for a, b in pairwise(counts)]
    return np.concatenate([[0], np.cumsum(steps)]).astype(float)


@dataclass(frozen=True)
class ConveyorFit:
    counts_per_mm: float  # signed: negative when the counter runs down as the belt travels
    counts_per_mm_uncertainty: float | None  # one standard uncertainty; None with two touches
    direction: np.ndarray  # unit vector of travel, base frame
    origin: np.ndarray  # the downstream touch on the fitted line, base frame
    z_axis: np.ndarray
    roll_from: str  # "side point (line N)" or "the robot base's z"
    residuals_mm: list[float]
    span_mm: float
    camera_offset_mm: float | None
    counter_bits: int
    warnings: tuple[str, ...]
    ticks: TickFit | None = None  # the robot's own decoder's scale (--ticks)

    def frame(self) -> np.ndarray:
        return belt2base(self.origin, self.direction, self.z_axis)

    def as_json(self) -> dict:
        return {
            "counts_per_mm": self.counts_per_mm,
            "counts_per_mm_uncertainty": self.counts_per_mm_uncertainty,
            "direction": self.direction.tolist(),
            "origin": self.origin.tolist(),
            "frame": self.frame().tolist(),
            "residuals_mm": self.residuals_mm,
            "camera_offset_mm": self.camera_offset_mm,
            "span_mm": self.span_mm,
            "roll_from": self.roll_from,
            "counter_bits": self.counter_bits,
            "warnings": list(self.warnings),
            "ticks_per_mm": None if self.ticks is None else self.ticks.ticks_per_mm,
            "ticks_per_mm_uncertainty": None if self.ticks is None else self.ticks.uncertainty,
            "ticks_per_count": None if self.ticks is None else self.ticks.ticks_per_count,
            "ticks_residuals_mm": None if self.ticks is None else self.ticks.residuals_mm,
        }


@dataclass(frozen=True)
class TickFit:
    """The robot's own decoder against the measured travel: ticks per mm (signed: negative when its ticks run down as
    the belt travels), its standard uncertainty (None with two touches), its ticks per count of the PLC's counter
    and each touch's distance from the fitted line by its ticks (mm along the belt)."""

    ticks_per_mm: float
    uncertainty: float | None
    ticks_per_count: float
    residuals_mm: list[float]


def fit_ticks(
    path: Path, belt: list[Touch], counts: np.ndarray, direction: np.ndarray, max_residual_mm: float
) -> TickFit:
    """T by a straight-line fit v_k = v_mean + T (s_k - s_mean): v the robot's unwrapped ticks, s each touch's
    measured place along the fitted direction (its own position, not the PLC's count); then the ticks against the
    PLC's counts at the same touches: both latched the same moment of the same travel, so a touch off that line is a
    latch/PLC mismatch, named as such."""
    missing = next((t for t in belt if t.ticks is None), None)
    if missing is not None:
        raise ConveyorCalibrationError(
            f"{path}:{missing.line}: --ticks needs the robot's tick count at every belt touch"
        )
    v = unwrap([t.ticks for t in belt], TICK_BITS)
    for (a, va), (b, vb) in pairwise(zip(belt, v, strict=True)):
        if va == vb:
            raise ConveyorCalibrationError(
                f"{path}:{b.line}: the same tick count as line {a.line}: the robot's encoder did not count (its "
                "decoder not enabled, encoder_enable_pulse_decode, or the encoder not wired to its inputs)"
            )
    s = np.array([t.position for t in belt]) @ direction
    ds, dv = s - s.mean(), v - v.mean()
    ticks_per_mm = float(ds @ dv / (ds @ ds))
    residuals = [float(r) for r in (ds - dv / ticks_per_mm)]
    du = counts - counts.mean()
    ratio = float(du @ dv / (du @ du))
    apart = (dv - ratio * du) / ticks_per_mm  # mm: the ticks' place against the PLC's count's
    worst = int(np.argmax(np.abs(apart)))
    if abs(apart[worst]) > max_residual_mm:
        raise ConveyorCalibrationError(
            f"{path}:{belt[worst].line}: the robot's tick count and the PLC's count disagree by "
            f"{abs(apart[worst]):.3f} mm of travel at this touch (more than {max_residual_mm:g} mm): a latch/PLC "
            "mismatch (one of the two read at another moment than the touch, or an encoder that slips)"
        )
    worst = int(np.argmax(np.abs(residuals)))
    if abs(residuals[worst]) > max_residual_mm:
        raise ConveyorCalibrationError(
            f"{path}:{belt[worst].line}: {abs(residuals[worst]):.3f} mm from the belt line fitted by the robot's ticks "
            f"(more than {max_residual_mm:g} mm): a cone that slipped or a tick count read at the wrong moment"
        )
    uncertainty = None
    if len(belt) > 2:
        sigma = math.sqrt(float(np.sum((dv - ticks_per_mm * ds) ** 2)) / (len(belt) - 2))  # ticks
        uncertainty = sigma / math.sqrt(float(ds @ ds))
    return TickFit(ticks_per_mm, uncertainty, ratio, [abs(r) for r in residuals])


def fit(
    path: Path,
    touches: list[Touch],
    bits: int,
    working_length_mm: float | None,
    camera_counts: tuple[int, int] | None = None,
    force: bool = False,
    max_residual_mm: float = MAX_RESIDUAL_MM,
    cell_direction: tuple[float, float, float] | None = None,
    ticks: bool = False,
) -> ConveyorFit:
    """E by a straight-line fit p_k = p_mean + b (u_k - u_mean) over every belt touch (u: unwrapped
    counts), E = 1/|b| signed by whether the counts grow downstream; +Y from the first touch towards the
    last (the belt carried the cone downstream); the origin at the last touch, on the fitted line; the
    roll from a side point, else from the base's z."""
    belt = [t for t in touches if t.role == "belt"]
    side = [t for t in touches if t.role == "side"]
    if len(belt) < MIN_TOUCHES:
        raise ConveyorCalibrationError(f"{path}: {len(belt)} belt touches; at least {MIN_TOUCHES} are needed")
    if len(side) > 1:
        raise ConveyorCalibrationError(f"{path}:{side[1].line}: more than one side point")
    u = unwrap([t.count for t in belt], bits)
    positions = np.array([t.position for t in belt])
    for (a, ua), (b, ub) in pairwise(zip(belt, u, strict=True)):
        if ua == ub:
            raise ConveyorCalibrationError(f"{path}:{b.line}: the same count as line {a.line}: the belt did not move")
    du = u - u.mean()
    slope = (du @ (positions - positions.mean(axis=0))) / (du @ du)  # mm per count, 3-vector
    mm_per_count = float(np.linalg.norm(slope))
    if not mm_per_count * float(np.ptp(u)) >= MIN_SPAN_MM:
        raise ConveyorCalibrationError(
            f"{path}: the belt touches lie within {mm_per_count * float(np.ptp(u)):.3f} mm of each other: the cone "
            f"must be touched at places at least {MIN_SPAN_MM:g} mm apart along the belt"
        )
    fitted = positions.mean(axis=0) + np.outer(du, slope)
    residuals = [float(v) for v in np.linalg.norm(positions - fitted, axis=1)]
    travel = fitted[-1] - fitted[0]
    sign = 1.0 if (u[-1] - u[0]) > 0 else -1.0  # counts grow as the belt carries the cone downstream
    direction = slope / mm_per_count * sign
    span = float(np.linalg.norm(travel))
    worst = max(range(len(residuals)), key=residuals.__getitem__)
    if residuals[worst] > max_residual_mm:
        raise ConveyorCalibrationError(
            f"{path}:{belt[worst].line}: {residuals[worst]:.3f} mm from the fitted belt line (more than "
            f"{max_residual_mm:g} mm): a cone that slipped, a count read at the wrong moment, or a counter of "
            f"another width than {bits} bit (its rollover breaks the line)"
        )
    warnings = []
    if cell_direction is not None and float(np.dot(direction, cell_direction)) < 0:
        message = (
            f"the touches give a belt running against the cell's direction {_vector(cell_direction)} (reversed): "
            "listed downstream first (the file takes the touches upstream first), or a counter that counts the "
            "other way"
        )
        if not force:
            raise ConveyorCalibrationError(f"{path}: {message}; reverse the rows, or --force to turn the belt round")
        warnings.append(message)
    if working_length_mm is None:
        if not force:
            raise ConveyorCalibrationError(
                f"{path}: the belt's working length is not known: give --working-length MM (or set "
                "working_length_mm in the cell's [conveyor]) so the span can be checked, or --force"
            )
        warnings.append("the span of the touches was not checked against the belt's working length")
    elif span < SPAN_SHARE * working_length_mm:
        message = (
            f"the touches span {span:.1f} mm, less than half the belt's working length ({working_length_mm:g} mm): "
            "E would be no better than the span allows (source 002 touches over 1/2 to 3/4 of the belt)"
        )
        if not force:
            raise ConveyorCalibrationError(f"{path}: {message}; touch further apart, or --force")
        warnings.append(message)
    uncertainty = None
    if len(belt) > 2:
        dof = 3 * (len(belt) - 2)
        sigma = math.sqrt(sum(r * r for r in residuals) / dof)  # per coordinate
        sigma_b = sigma / math.sqrt(float(du @ du))  # of the slope, mm per count
        uncertainty = sigma_b / mm_per_count**2
    else:
        warnings.append("two touches: E follows from them exactly, with no residual to judge it by")
    z_axis, roll_from = _normal(path, direction, fitted[-1], side)
    tick_fit = fit_ticks(path, belt, u, direction, max_residual_mm) if ticks else None
    if tick_fit is not None and abs(abs(tick_fit.ticks_per_count) - 1.0) > TICK_SCALE_TOL:
        warnings.append(
            f"the robot's decoder counts {tick_fit.ticks_per_count:.6f} ticks per count of the PLC's counter: the two "
            "count at different scales (another encoder, or another decoding); the UR program tracks by the robot's "
            "ticks_per_mm and places the parts by the PLC's counts_per_mm"
        )
    camera = None
    if camera_counts is not None:
        steps = unwrap(list(camera_counts), bits)
        camera = float(steps[1]) / (sign / mm_per_count)
        if not camera > 0:
            warnings.append(
                f"the camera comes out {camera:.3f} mm along the belt from the origin, not upstream of it: "
                "were L3 and L4 given in that order (L3 at the camera, L4 at the origin)?"
            )
    return ConveyorFit(
        counts_per_mm=sign / mm_per_count,
        counts_per_mm_uncertainty=uncertainty,
        direction=direction,
        origin=fitted[-1],
        z_axis=z_axis,
        roll_from=roll_from,
        residuals_mm=residuals,
        span_mm=span,
        camera_offset_mm=camera,
        counter_bits=bits,
        warnings=tuple(warnings),
        ticks=tick_fit,
    )


def _normal(path: Path, direction: np.ndarray, origin: np.ndarray, side: list[Touch]) -> tuple[np.ndarray, str]:
    """The belt's normal, up: from the side point (the plane of the belt through its line), else the base's
    z made square to the belt. Two touches along the belt leave the roll about it open (source 002)."""
    base_z = np.array([0.0, 0.0, 1.0])
    if side:
        across = side[0].position - origin
        across = across - (across @ direction) * direction
        if np.linalg.norm(across) < 10.0:
            raise ConveyorCalibrationError(
                f"{path}:{side[0].line}: the side point is {np.linalg.norm(across):.1f} mm from the belt's line: "
                "at least 10 mm beside it"
            )
        normal = np.cross(across, direction)
        normal /= np.linalg.norm(normal)
        if normal @ base_z < 0:
            normal = -normal
        return normal, f"the side point (line {side[0].line})"
    normal = base_z - (base_z @ direction) * direction
    if np.linalg.norm(normal) < 0.1:
        raise ConveyorCalibrationError(f"{path}: the belt runs within 6 deg of the base's z: touch a side point")
    return normal / np.linalg.norm(normal), "the robot base's z"


def report_lines(result: ConveyorFit, path: Path) -> list[str]:
    e, u = result.counts_per_mm, result.counts_per_mm_uncertainty
    lines = [
        f"conveyor from {path.name}: {len(result.residuals_mm)} belt touches over {result.span_mm:.1f} mm",
        f"  E = {e:.6f} counts/mm"
        + (f" +- {u:.6f} (one standard uncertainty)" if u is not None else "")
        + ("  (the counter runs down as the belt travels)" if e < 0 else ""),
        "  direction of travel (+Y, base frame): " + ", ".join(f"{v:.6f}" for v in result.direction),
        "  origin (the downstream touch, on the fitted line): " + ", ".join(f"{v:.3f}" for v in result.origin),
        "  belt normal (+Z): " + ", ".join(f"{v:.6f}" for v in result.z_axis) + f" (roll from {result.roll_from})",
        "  residuals (mm): " + ", ".join(f"{r:.3f}" for r in result.residuals_mm),
    ]
    if result.ticks is not None:
        t = result.ticks
        lines.append(
            f"  robot's ticks T = {t.ticks_per_mm:.6f} ticks/mm"
            + (f" +- {t.uncertainty:.6f}" if t.uncertainty is not None else "")
            + f", {t.ticks_per_count:.6f} per PLC count; residuals (mm): "
            + ", ".join(f"{r:.3f}" for r in t.residuals_mm)
        )
    if result.camera_offset_mm is not None:
        lines.append(f"  camera line {result.camera_offset_mm:.3f} mm upstream of the origin, along the belt")
    lines += [f"warning: {w}" for w in result.warnings]
    return lines


def write_to_cell(cell_path: Path, result: ConveyorFit, source: str, working_length_mm: float | None) -> None:
    """Replace (or add) the cell's [conveyor] table, keeping a camera offset this calibration did not
    measure; the comments before the next table stay; the edited file must load and pass every kind's reach
    proof (a belt's window, ...) before it replaces the old one (its mode and a symlink kept)."""

    previous = conveyor_of(load_cell(cell_path))
    camera = result.camera_offset_mm
    if camera is None and previous is not None:
        camera = previous.camera_offset_mm
    # the robot's own scale: this calibration's, else the one before (its encoder is not the PLC's counter)
    ticks = result.ticks.ticks_per_mm if result.ticks is not None else None
    if ticks is None and previous is not None:
        ticks = previous.ticks_per_mm

    def vector(values) -> str:
        return "[" + ", ".join(f"{float(v):.12g}" for v in values) + "]"

    lines = [f"[conveyor]                        # `codegen calibrate conveyor` from {source}"]
    lines.append(f"counter_bits = {result.counter_bits}")
    lines.append(f"counts_per_mm = {result.counts_per_mm:.12g}")
    lines.append(f"origin = {vector(result.origin)}")
    lines.append(f"direction = {vector(result.direction)}")
    lines.append(f"z_axis = {vector(result.z_axis)}")
    if ticks is not None:
        lines.append(f"ticks_per_mm = {ticks:.12g}")
    if camera is not None:
        lines.append(f"camera_offset_mm = {camera:.12g}")
    if working_length_mm is not None:
        lines.append(f"working_length_mm = {working_length_mm:.12g}")
    table = "\n".join(lines) + "\n"
    read_cell_data(cell_path)  # a cell file at all; CellError: the command's message

    def edit(text: str) -> str:
        start, end = _table_span(text, "conveyor")
        return text[:start] + table + text[end:] if start is not None else text.rstrip("\n") + "\n\n" + table

    try:
        replace_cell_file(cell_path, edit, prove=clears)
    except CellError as exc:
        raise ConveyorCalibrationError(f"{cell_path}: edited file would not load: {exc}") from None
    except ReachError as exc:
        raise ConveyorCalibrationError(f"{cell_path}: with this belt the cell would not generate: {exc}") from None
    except WriteRefused as exc:
        raise ConveyorCalibrationError(str(exc)) from None
    except OSError as exc:
        raise ConveyorCalibrationError(
            f"{cell_path}: cannot write: {exc.strerror or exc}; the file was left as it was"
        ) from None


def _table_span(text: str, name: str) -> tuple[int | None, int]:
    """Where the table [name] is in a TOML text: its header line to its last key line (the blank and
    comment lines after it belong to what follows); (None, 0) when there is none."""
    lines = text.splitlines(keepends=True)
    offsets = [0]
    for line in lines:
        offsets.append(offsets[-1] + len(line))
    header = next((i for i, line in enumerate(lines) if line.strip().split("#")[0].strip() == f"[{name}]"), None)
    if header is None:
        return None, 0
    last = header
    for i in range(header + 1, len(lines)):
        stripped = lines[i].strip()
        if stripped.startswith("["):
            break
        if stripped and not stripped.startswith("#"):
            last = i
    return offsets[header], offsets[last + 1]


def cell_settings(cell_path: Path | None) -> tuple[int | None, float | None, tuple[float, float, float] | None]:
    """The counter width, working length and direction of travel a cell's [conveyor] names, if any."""
    if cell_path is None:
        return None, None, None

    conveyor = conveyor_of(load_cell(cell_path))
    if conveyor is None:
        return None, None, None
    return conveyor.counter_bits, conveyor.working_length_mm, conveyor.direction


def _vector(values) -> str:
    return "[" + ", ".join(f"{float(v):.3f}" for v in values) + "]"
