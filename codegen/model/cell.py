"""Cell file (TOML) to a validated, frozen model; errors name the file and the key path."""

from __future__ import annotations

import hashlib
import math
import tomllib
from dataclasses import dataclass, field, replace
from functools import cached_property, lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from codegen.controllers import target_names
from codegen.guard import READING_RANGE_MM, TAUGHT_RANGE_MM
from codegen.model import io, motion, tables, vision
from codegen.model.io import SignalSettings
from codegen.model.motion import MotionSettings
from codegen.model.robot import Robot, parse_robot, parse_station_config
from codegen.model.tables import (
    CAMERA,
    CELL_POSE_FORMATS,
    DEFAULT_MODE,
    LIMITS,
    STATION_ID_MAX,
    VISION_TABLES,
)
from codegen.model.validate import CellError, Validator, kind_of
from codegen.model.vision import VisionSettings
from codegen.output import replace_file
from codegen.poses import POSE_FORMATS
from codegen.protocol import get_kind, kinds, station_kinds
from codegen.readfile import ReadError, read_regular

QUATERNION_TOLERANCE = 1e-6
QUATERNION_BOUND = 10.0  # a quaternion that far from unit length is a typing error, not a rotation
# The unit of the orientation values per cell pose format: Euler angles in degrees, rotation vector
# components in radians, each within one turn (Validator.angles; abb: a quaternion, normalised)
ORIENTATION_UNITS = {"xyzabc": "deg", "ur": "rad"}

EXAMPLES_DIR = Path(__file__).parents[1] / "examples"
DEMO_CELL = EXAMPLES_DIR / "agv_machine_tending.toml"


@dataclass(frozen=True)
class Limits:
    max_shift_mm: float
    max_rotation_deg: float


@dataclass(frozen=True)
class TaughtPose:
    name: str
    values: tuple[float, ...]  # as written in the cell file (after quaternion normalisation)
    pose_format: str

    def matrix(self) -> np.ndarray:
        """pose2base, 4x4 float64 in mm (computed once per pose; read-only)."""
        return _pose_matrix(self.pose_format, self.values)


@lru_cache(maxsize=65536)
def _pose_matrix(pose_format: str, values: tuple[float, ...]) -> np.ndarray:
    matrix = POSE_FORMATS[pose_format][1](values)
    matrix.flags.writeable = False
    return matrix


@dataclass(frozen=True)
class Station:
    id: int
    name: str
    poses: tuple[TaughtPose, ...]  # visiting order: first joint move, then linear
    kind: str  # the program kind (codegen/kinds/): the cell file's `mode` key
    spec: Any  # the kind's own data, e.g. PointSpec or FrameSpec
    config: dict = field(default_factory=dict, compare=False)  # target -> pose -> PoseConfig ([station.config])
    retreat: TaughtPose | None = None  # the work pose backed off along its z axis ([cell.motion] retreat_mm)

    @property
    def path(self) -> tuple[TaughtPose, ...]:
        """The poses the arm visits in the station: the taught ones (the last is the work pose), then
        the retreat."""
        return self.poses if self.retreat is None else (*self.poses, self.retreat)


@dataclass(frozen=True)
class Cell:
    name: str
    targets: tuple[str, ...]
    pose_format: str
    angle_sign: int
    limits: Limits
    stations: tuple[Station, ...]
    handeye: tuple[tuple[float, float, float], tuple[float, float, float]] | None = None  # pixel -> mm
    settings: dict = field(default_factory=dict, compare=False)  # kind name -> its [cell.<table>] settings
    robot: Robot | None = None  # [cell.robot] and [cell.tool]; None: the cell names no arm
    vision: VisionSettings = field(default_factory=VisionSettings)  # [cell.vision]: the handshake's timeout
    motion: MotionSettings = field(default_factory=MotionSettings)  # [cell.motion]: speeds, zones, retreat, home
    io: SignalSettings | None = None  # [cell.io]: the work pose's output and its feedback
    source: str = ""
    sha256: str = ""
    warnings: tuple[str, ...] = field(default=(), compare=False)
    sections: dict = field(default_factory=dict, compare=False)  # kind name -> its part of the cell (its tables)

    def station_by_id(self, station_id: int) -> Station | None:
        return self._stations_by_id.get(station_id)

    @cached_property
    def _stations_by_id(self) -> dict[int, Station]:
        return {station.id: station for station in self.stations}


# --- loading ---------------------------------------------------------------------------------

STATIONS_MAX = 5000  # the scale issue's largest cell: its programs load and run here (a UR program in about 35 s)
POSES_MAX = 1000  # a station's poses are one run: 1,000 take about a tenth of verify's step limit


def image_angle_sign(pixel_to_mm) -> int:
    """The angle sign a camera's image imposes: -1 when the hand-eye map mirrors (negative determinant),
    since a turn of the mark then turns the other way in the image's axes."""
    (a, b, _), (c, d, _) = pixel_to_mm
    return -1 if a * d - b * c < 0 else 1


# a cell of 10,000 stations is about 5 MB; beyond this bound a file is no cell this tool can work with
CELL_FILE_MAX_BYTES = 64 << 20
CELL_FILE_BOUND = "a cell of 10,000 stations is about 5 MB"


def load_cell(path: str | Path | None = None) -> Cell:
    """Load and validate a cell file; None means the bundled demo cell."""
    path = Path(path) if path is not None else DEMO_CELL
    data, raw = read_cell_data(path)
    try:
        return cell_from_dict(data, source=str(path), sha256=hashlib.sha256(raw).hexdigest())
    except RecursionError:
        raise CellError(f"{path}: tables or arrays nested too deeply") from None
    except CellError as exc:
        raise exc.with_line(raw.decode("utf-8", errors="replace")) from None


def read_cell_data(path: Path) -> tuple[dict, bytes]:
    """A cell file's TOML tables and its bytes; a CellError naming the file when it cannot be read."""
    try:
        raw = read_regular(path, CELL_FILE_MAX_BYTES, "a cell file (TOML)", CELL_FILE_BOUND, "cannot read cell file")
    except ReadError as exc:
        raise CellError(str(exc)) from None
    return parse_cell_bytes(raw, path), raw


def parse_cell_bytes(raw: bytes, path: Path) -> dict:
    """A cell file's TOML tables from its bytes; a CellError naming `path` when they are no cell file's."""
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise CellError(f"{path}: not UTF-8 text (byte {exc.start})") from None
    try:
        data = tomllib.loads(text)
    except RecursionError:
        raise CellError(f"{path}: tables or arrays nested too deeply") from None
    except tomllib.TOMLDecodeError as exc:
        raise CellError(f"{path}: TOML syntax error: {exc}") from None
    except ValueError:  # an integer too long for Python to read (more than 4300 digits)
        raise CellError(f"{path}: a number with thousands of digits: no controller's number holds it") from None
    return data


def replace_cell_file(path: Path, text: str) -> None:
    """Replace a cell file by an edited text (a calibration's --write) once the edited text loads and passes
    every kind's reach proof (the cell still generates); the file keeps its mode, a symlink stays and its target
    is replaced (codegen.output.replace_file). Otherwise the file stays as it was and the error goes to the
    caller: CellError, ReachError, or OSError when the file cannot be written."""

    def accept(written: Path) -> None:
        raw = written.read_bytes()  # what is on disk, named as the cell file it will become
        try:
            cell = cell_from_dict(parse_cell_bytes(raw, path), source=str(path), sha256=hashlib.sha256(raw).hexdigest())
        except RecursionError:
            raise CellError(f"{path}: tables or arrays nested too deeply") from None
        except CellError as exc:
            raise exc.with_line(raw.decode("utf-8", errors="replace")) from None
        for kind in kinds().values():
            kind.reach(cell, list(cell.targets))

    replace_file(path, text, accept)


def cell_from_dict(data: dict, source: str = "<cell>", sha256: str = "") -> Cell:
    ctx = CellValidator(source)
    known_tables = tables.file_table().allowed
    top_unknown = set(data) - known_tables
    if top_unknown:
        listed = ", ".join(f"[{t}]" for t in sorted(known_tables))
        ctx.fail(sorted(top_unknown)[0], f"unknown table; expected {listed}")
    cell_table = ctx.table(data, "cell", "cell")
    definition = tables.cell_table()  # the cell file's definition (codegen/model/tables.py), with the kinds' tables
    ctx.no_unknown(cell_table, definition.allowed, "cell")

    name = ctx.name(cell_table, "name", "cell.name")
    known_targets = target_names()
    targets_raw = ctx.require(cell_table, "targets", "cell.targets")
    if not isinstance(targets_raw, list) or not targets_raw:
        ctx.fail("cell.targets", f"expected a non-empty list of targets from {list(known_targets)}")
    targets: list[str] = []
    for i, target in enumerate(targets_raw):
        if target not in known_targets:
            ctx.fail(f"cell.targets[{i}]", f"unknown target {target!r}; known: {', '.join(known_targets)}")
        if target in targets:
            ctx.fail(f"cell.targets[{i}]", f"target {target!r} listed twice")
        targets.append(target)

    pose_format = cell_table.get("pose_format", definition.default("pose_format"))
    if pose_format not in CELL_POSE_FORMATS:
        ctx.fail("cell.pose_format", f"unknown pose format {pose_format!r}; known: {', '.join(CELL_POSE_FORMATS)}")

    robot = parse_robot(ctx, cell_table, tuple(targets), pose_format)

    # a cell of a kind that reads no mark (its tables alone: kind.standalone) needs no camera and no limits
    vision_free = not data.get("station") and any(kind.standalone(data) for kind in kinds().values())
    if vision_free:
        camera_unused, limits_unused = VISION_TABLES
        unused = {camera_unused: {"angle_sign": 1}, limits_unused: {"max_shift_mm": 10.0, "max_rotation_deg": 10.0}}
        cell_table = {**unused, **cell_table}
    camera = ctx.table(cell_table, "camera", "cell.camera")
    ctx.no_unknown(camera, CAMERA.allowed, "cell.camera")
    angle_sign = ctx.require(camera, "angle_sign", "cell.camera.angle_sign")
    if isinstance(angle_sign, bool) or angle_sign not in CAMERA["angle_sign"].choices:
        ctx.fail("cell.camera.angle_sign", f"expected 1 or -1, got {angle_sign!r}")

    handeye = None
    if "handeye" in camera:
        he = ctx.table(camera, "handeye", "cell.camera.handeye")
        ctx.no_unknown(he, CAMERA["handeye"].table.allowed, "cell.camera.handeye")
        rows = ctx.require(he, "pixel_to_mm", "cell.camera.handeye.pixel_to_mm")
        if not isinstance(rows, list) or len(rows) != 2:
            ctx.fail("cell.camera.handeye.pixel_to_mm", "expected 2 rows of 3 numbers [[a, b, tx], [c, d, ty]]")
        handeye = tuple(ctx.numbers(r, 3, f"cell.camera.handeye.pixel_to_mm[{i}]") for i, r in enumerate(rows))
        det = handeye[0][0] * handeye[1][1] - handeye[0][1] * handeye[1][0]
        if max(abs(v) for row in handeye for v in row) > READING_RANGE_MM or not abs(det) >= 1e-12:
            ctx.fail(
                "cell.camera.handeye.pixel_to_mm",
                f"the 2x2 part is singular, or an entry is beyond +-{READING_RANGE_MM:g}",
            )
        if angle_sign != image_angle_sign(handeye):
            ctx.fail(
                "cell.camera.angle_sign",
                f"the hand-eye map's determinant is {'negative' if det < 0 else 'positive'}: the image is "
                f"{'' if det < 0 else 'not '}mirrored, so the camera's angles turn "
                f"{'against' if det < 0 else 'with'} the frame's and angle_sign must be {image_angle_sign(handeye)} "
                "(`codegen calibrate handeye POINTS.csv --write CELL` sets it)",
            )

    settings = {kind.name: kind.parse_settings(ctx, cell_table) for kind in kinds().values()}

    limits_table = ctx.table(cell_table, "limits", "cell.limits")
    ctx.no_unknown(limits_table, LIMITS.allowed, "cell.limits")
    max_shift = ctx.number(limits_table, "max_shift_mm", "cell.limits.max_shift_mm")
    max_rot = ctx.number(limits_table, "max_rotation_deg", "cell.limits.max_rotation_deg")
    shift_key, rot_key = LIMITS["max_shift_mm"], LIMITS["max_rotation_deg"]
    if max_shift <= shift_key.low:
        ctx.fail("cell.limits.max_shift_mm", f"must be positive, got {max_shift}")
    if max_shift > shift_key.high:
        ctx.fail("cell.limits.max_shift_mm", f"must be at most {shift_key.high:g} mm")
    if not rot_key.contains(max_rot):
        ctx.fail("cell.limits.max_rotation_deg", f"must be in {rot_key.range_text()} degrees, got {max_rot}")

    stations_raw = data.get("station", [] if vision_free else None)
    if not isinstance(stations_raw, list) or not (stations_raw or vision_free):
        ctx.fail("station", "expected at least one [[station]] table, or the tables of a program kind that needs none")
    if len(stations_raw) > STATIONS_MAX:
        ctx.fail(
            "station",
            f"{len(stations_raw)} stations; at most {STATIONS_MAX} (the largest cell whose programs are verified "
            "to load and run in the interpreter here)",
        )
    stations = [ctx.station(raw, i + 1, pose_format) for i, raw in enumerate(stations_raw)]
    stations = [
        replace(
            station,
            config=parse_station_config(
                ctx, raw.get("config"), f"station[{i}].config", robot, [p.name for p in station.poses]
            ),
        )
        for i, (station, raw) in enumerate(zip(stations, stations_raw, strict=True), start=1)
    ]
    motion_settings = motion.parse_settings(ctx, cell_table)
    if motion_settings.retreat_mm > 0:
        stations = [replace(s, retreat=_retreat(s, motion_settings.retreat_mm, pose_format)) for s in stations]
    seen_ids: dict[int, int] = {}
    seen_names: dict[str, int] = {}
    for i, station in enumerate(stations, start=1):
        if station.id in seen_ids:
            ctx.fail(f"station[{i}].id", f"duplicate station id {station.id} (also station[{seen_ids[station.id]}])")
        if station.name in seen_names:
            other = seen_names[station.name]
            ctx.fail(f"station[{i}].name", f"duplicate station name {station.name!r} (also station[{other}])")
        seen_ids[station.id] = i
        seen_names[station.name] = i
    cell = Cell(
        name=name,
        targets=tuple(targets),
        pose_format=pose_format,
        angle_sign=int(angle_sign),
        limits=Limits(max_shift, max_rot),
        stations=tuple(stations),
        handeye=handeye,
        settings=settings,
        robot=robot,
        vision=vision.parse_settings(ctx, cell_table),
        motion=motion_settings,
        io=io.parse_settings(ctx, cell_table, targets),
        source=source,
        sha256=sha256,
        warnings=tuple(ctx.warnings),
    )
    sections = {}
    for kind in kinds().values():  # each kind's own tables, with what the cell knows so far
        section = kind.parse_section(ctx, data, cell)
        if section is not None:
            sections[kind.name] = section
    cell = replace(cell, sections=sections, warnings=tuple(ctx.warnings))
    for i, station in enumerate(stations, start=1):
        get_kind(station.kind).check_station(ctx, f"station[{i}]", station, cell)
    for kind in kinds().values():
        kind.check_cell(ctx, cell)
    return cell


def _retreat(station: Station, retreat_mm: float, pose_format: str) -> TaughtPose:
    """The station's work pose backed off along its own z axis, in the cell's pose format."""
    work2base = station.poses[-1].matrix() @ motion.retreat2work(retreat_mm)
    values = tuple(float(v) + 0.0 for v in POSE_FORMATS[pose_format][2](work2base))  # + 0.0: no -0.0
    return TaughtPose("retreat", values, pose_format)


class CellValidator(Validator):
    """The validator with the [[station]] and taught-pose rules of the cell file."""

    def station(self, raw, index: int, pose_format: str) -> Station:
        path = f"station[{index}]"
        if not isinstance(raw, dict):
            self.fail(path, f"expected a table, got {kind_of(raw)}")
        station_id = self.require(raw, "id", f"{path}.id")
        if isinstance(station_id, bool) or not isinstance(station_id, int):
            self.fail(f"{path}.id", f"expected an integer, got {kind_of(station_id)}")
        if not 1 <= station_id <= STATION_ID_MAX:
            self.fail(f"{path}.id", f"must be in 1..{STATION_ID_MAX}, got {station_id}")
        name = self.name(raw, "name", f"{path}.name")
        known = station_kinds()
        mode = raw.get("mode", DEFAULT_MODE)
        if not isinstance(mode, str) or mode not in known:
            self.fail(f"{path}.mode", f"expected one of {', '.join(map(repr, known))}, got {mode!r}")
        kind = known[mode]
        common = tables.station_table().allowed
        for key in sorted(set(raw) - common - kind.station_keys):
            owners = [k.name for k in known.values() if key in k.station_keys]
            if owners:
                self.fail(f"{path}.{key}", f'only {owners[0]} stations (mode = "{owners[0]}") have this key')
            allowed = ", ".join(sorted(common | kind.station_keys))
            self.fail(f"{path}.{key}", f"unknown key; allowed: {allowed}")
        spec = kind.parse(self, raw, path, pose_format)
        poses_raw = self.table(raw, "poses", f"{path}.poses")
        if not poses_raw:
            self.fail(f"{path}.poses", "a station needs at least one pose")
        if len(poses_raw) > POSES_MAX:
            self.fail(f"{path}.poses", f"{len(poses_raw)} poses; at most {POSES_MAX} per station")
        poses = [
            self.pose(pose_name, values, f"{path}.poses.{pose_name}", pose_format)
            for pose_name, values in poses_raw.items()
        ]
        return Station(int(station_id), name, tuple(poses), mode, spec)

    def pose(self, pose_name: str, values, pose_path: str, pose_format: str) -> TaughtPose:
        if not pose_name.strip():
            self.fail(pose_path, "pose name must not be empty")
        numbers = self.orientation(
            self.numbers(values, POSE_FORMATS[pose_format][0], pose_path), pose_path, pose_format
        )
        if pose_format == "abb":
            numbers = self.normalise_quaternion(numbers, pose_path)
        bound = TAUGHT_RANGE_MM / (1000.0 if pose_format == "ur" else 1.0)
        if max(abs(v) for v in numbers[:3]) > bound:
            self.fail(pose_path, f"position must be within +-{bound:g} (cell units)")
        return TaughtPose(pose_name, numbers, pose_format)

    def orientation(self, numbers: tuple[float, ...], path: str, pose_format: str) -> tuple[float, ...]:
        """A pose's values with its orientation (after x, y, z) checked: angles within one turn."""
        if pose_format in ORIENTATION_UNITS:
            self.angles(numbers[3:], path, ORIENTATION_UNITS[pose_format], "orientation values")
        return numbers

    def normalise_quaternion(self, numbers: tuple[float, ...], path: str) -> tuple[float, ...]:
        q = numbers[3:]
        if max(abs(v) for v in q) > QUATERNION_BOUND:
            bound = QUATERNION_BOUND
            self.fail(path, f"quaternion q1..q4 must be within +-{bound:g} (a unit quaternion's are within +-1)")
        norm = math.sqrt(sum(v * v for v in q))
        if norm < 1e-9:
            self.fail(path, "quaternion q1..q4 is zero")
        if abs(norm - 1.0) > QUATERNION_TOLERANCE:
            self.warnings.append(f"{self.source}: {path}: quaternion norm {norm:.9g} normalised to 1")
        return numbers[:3] + tuple(v / norm for v in q)
