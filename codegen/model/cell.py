"""Cell file (TOML) to a validated, frozen model; errors name the file and the key path."""

from __future__ import annotations

import hashlib
import math
import tomllib
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from codegen.exactcache import exact_cache
from codegen.guard import TAUGHT_RANGE_MM
from codegen.model import io, motion, tables, vision, world
from codegen.model.hints import missing_hint
from codegen.model.io import SignalSettings
from codegen.model.loader import Loader
from codegen.model.motion import MotionSettings
from codegen.model.robot import Robot, parse_robot
from codegen.model.validate import CellError, Validator, kind_of, metres_hint
from codegen.model.vision import VisionSettings
from codegen.model.world import WorldSettings
from codegen.poses import POSE_FORMATS
from codegen.protocol import Kinds, installed_kinds
from codegen.readfile import ReadError, read_regular
from codegen.writefile import replace_file

QUATERNION_TOLERANCE = 1e-6
QUATERNION_BOUND = 10.0  # a quaternion that far from unit length is a typing error, not a rotation
# The unit of the orientation values per cell pose format: Euler angles in degrees, rotation vector
# components in radians, each within one turn (Validator.angles; abb: a quaternion, normalised)
ORIENTATION_UNITS = {"xyzabc": "deg", "ur": "rad"}

EXAMPLES_DIR = Path(__file__).parents[1] / "examples"
DEMO_CELL = EXAMPLES_DIR / "agv_machine_tending.toml"
EXAMPLE_PLANT = EXAMPLES_DIR / "plant"  # a plant of its own (codegen.toml, its output beside it)


def example_cells() -> list[Path]:
    """The bundled example cells whose output is committed under generated/ (the example plant's are apart)."""
    return sorted(p for p in EXAMPLES_DIR.rglob("*.toml") if EXAMPLE_PLANT not in p.parents)


@dataclass(frozen=True)
class TaughtPose:
    name: str
    values: tuple[float, ...]  # as written in the cell file (after quaternion normalisation)
    pose_format: str

    def matrix(self) -> np.ndarray:
        """pose2base, 4x4 float64 in mm (computed once per pose; read-only)."""
        return _pose_matrix(self.pose_format, self.values)


def _format_hint(pose_format: str, count: int) -> str:
    """What the cell's pose format takes, and which format a pose of count numbers would be."""
    others = [f'pose_format = "{name}" ({spec[3]})' for name, spec in POSE_FORMATS.items() if spec[0] == count]
    said = f' (pose_format = "{pose_format}" takes {POSE_FORMATS[pose_format][3]}'
    return said + (f"; {count} numbers are a pose of {' or '.join(others)})" if others else ")")


@exact_cache(maxsize=65536)
def _pose_matrix(pose_format: str, values: tuple[float, ...]) -> np.ndarray:
    matrix = POSE_FORMATS[pose_format][1](values)
    matrix.flags.writeable = False
    return matrix


@dataclass(frozen=True)
class Cell:
    name: str
    targets: tuple[str, ...]
    pose_format: str
    settings: dict = field(default_factory=dict, compare=False)  # kind name -> its [cell.<table>] settings
    robot: Robot | None = None  # [cell.robot] and [cell.tool]; None: the cell names no arm
    vision: VisionSettings = field(default_factory=VisionSettings)  # [cell.vision]: the handshake's timeout
    motion: MotionSettings = field(default_factory=MotionSettings)  # [cell.motion]: speeds, zones, retreat, home
    io: SignalSettings | None = None  # [cell.io]: the work pose's output and its feedback
    world: WorldSettings = field(default_factory=WorldSettings)  # [cell.world]: the floor, solids, clearance
    source: str = ""
    sha256: str = ""
    warnings: tuple[str, ...] = field(default=(), compare=False)
    sections: dict = field(default_factory=dict, compare=False)  # kind name -> its part of the cell (its tables)
    kinds: Kinds | None = field(default=None, compare=False, repr=False)  # the kinds the cell was loaded with
    # (kind name, target) -> the kind's plan for this cell (codegen.protocol.Kind.plan): made once, where first asked;
    # not an argument, so a cell made from this one by dataclasses.replace starts with none
    plans: dict = field(default_factory=dict, init=False, compare=False, repr=False)

    def stations_section(self):
        """The section that carries the cell's stations, whichever kind's it is (a section with `stations`, and the
        `limits` their readings are held to); None: no section does. Code outside the kinds asks this (the guard's
        messages, verify's large cells, a program that shares the station program's name) instead of naming the
        kind."""
        return next((s for s in self.sections.values() if hasattr(s, "stations")), None)


# --- loading ---------------------------------------------------------------------------------

# a cell of 10,000 stations is about 5 MB; beyond this bound a file is no cell this tool can work with
CELL_FILE_MAX_BYTES = 64 << 20
CELL_FILE_BOUND = "a cell of 10,000 stations is about 5 MB"


def load_cell(path: str | Path | None = None, kinds: Kinds | None = None) -> Cell:
    """Load and validate a cell file (None: the bundled demo cell) with the program kinds given (default: the installed
    ones, codegen.protocol.installed_kinds); the cell carries them to generate, verify and the page."""
    path = Path(path) if path is not None else DEMO_CELL
    data, raw = read_cell_data(path)
    try:
        return cell_from_dict(data, source=str(path), sha256=hashlib.sha256(raw).hexdigest(), kinds=kinds)
    except RecursionError:
        raise CellError(f"{path}: tables or arrays nested too deeply") from None
    except CellError as exc:
        raise _explained(exc, kinds, data).with_line(raw.decode("utf-8", errors="replace")) from None


def _explained(exc: CellError, kinds: Kinds | None, data: dict) -> CellError:
    """A missing key's error with what the key is for and a minimal example of it (codegen/model/hints.py), a
    controller's value for each of the cell's targets."""
    if not exc.key or not exc.detail.startswith("missing"):
        return exc
    cell = data.get("cell")
    targets = cell.get("targets") if isinstance(cell, dict) else None
    targets = tuple(t for t in targets if isinstance(t, str)) if isinstance(targets, list) else ()
    doc, example = missing_hint(tables.file_table(installed_kinds() if kinds is None else kinds), exc.key, targets)
    if not example:
        return exc
    said = exc.detail if exc.detail != "missing" else f"missing: {doc}"
    detail = f"{said}. For example:\n{example}"
    return CellError(f"{exc.source}: {exc.key}: {detail}", exc.source, exc.key, detail)


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


def replace_cell_file(
    path: Path, edit: Callable[[str], str], kinds: Kinds | None = None, prove: Callable[[Cell], None] | None = None
) -> str:
    """Replace a cell file by `edit(its text)` (a calibration's --write) once the edited text loads and passes
    every kind's reach proof and `prove` (generate's clearance proof, codegen.generate.clears: the cell still
    generates). The text is read again
    under a lock beside the file, so two calibrations of one cell at once both land; the file keeps its mode and
    line ends, a symlink stays and its target is replaced (codegen.writefile.replace_file). Otherwise the file
    stays as it was and the error goes to the caller: CellError, ReachError (a clearance refusal too), WriteRefused
    (hard links, read-only, not a regular file), or OSError when the file cannot be written. Returns the text
    written."""

    def accept(written: Path) -> None:
        raw = written.read_bytes()  # what is on disk, named as the cell file it will become
        data: dict = {}
        try:
            digest = hashlib.sha256(raw).hexdigest()
            data = parse_cell_bytes(raw, path)
            cell = cell_from_dict(data, source=str(path), sha256=digest, kinds=kinds)
        except RecursionError:
            raise CellError(f"{path}: tables or arrays nested too deeply") from None
        except CellError as exc:
            raise _explained(exc, kinds, data).with_line(raw.decode("utf-8", errors="replace")) from None
        for kind in cell.kinds.values():
            kind.writer.reach(cell, list(cell.targets))
        if prove is not None:
            prove(cell)

    return replace_file(path, edit, accept)


def cell_from_dict(data: dict, source: str = "<cell>", sha256: str = "", kinds: Kinds | None = None) -> Cell:
    """A cell from a cell file's tables, read by the kinds given (default: the installed ones)."""
    kinds = installed_kinds() if kinds is None else kinds
    ctx = CellValidator(source)
    known_tables = tables.file_table(kinds).allowed
    top_unknown = set(data) - known_tables
    if top_unknown:
        listed = ", ".join(f"[{t}]" for t in sorted(known_tables))
        ctx.fail(sorted(top_unknown)[0], f"unknown table; expected {listed}")
    for name, key in tables.file_table(kinds).keys.items():  # each kind's tables first: a kind reads only tables
        if name in data:
            _table_shape(ctx, name, key.type, data[name])
    cell_table = ctx.table(data, "cell", "cell")
    definition = tables.cell_table(kinds)  # the cell file's definition (codegen/model/tables.py) with the kinds'
    ctx.no_unknown(cell_table, definition.allowed, "cell")

    written = {key: cell_table[key] for key in tables.OWN_KEYS if key in cell_table}  # its tables: by their sections
    own = Loader(ctx).table(tables.own_table(kinds), written, "cell")
    name, targets, pose_format = own["name"], own["targets"], own["pose_format"]

    robot = parse_robot(ctx, cell_table, targets, pose_format)

    settings = {kind.name: kind.section.settings(ctx, cell_table) for kind in kinds.values()}
    cell = Cell(
        name=name,
        targets=targets,
        pose_format=pose_format,
        settings=settings,
        robot=robot,
        vision=vision.parse_settings(ctx, cell_table),
        motion=motion.parse_settings(ctx, cell_table),
        io=io.parse_settings(ctx, cell_table, targets),
        world=world.parse_settings(ctx, cell_table, pose_format),
        source=source,
        sha256=sha256,
        warnings=tuple(ctx.warnings),
        kinds=kinds,
    )
    sections = {}
    for kind in kinds.values():  # each kind's own tables, with what the cell knows so far
        section = kind.section.parse(ctx, data, cell)
        if section is not None:
            sections[kind.name] = section
    cell = replace(cell, sections=sections, warnings=tuple(ctx.warnings))
    for kind in kinds.values():
        kind.section.check(ctx, cell)
    return cell


def _table_shape(ctx: Validator, name: str, shape: str, value) -> None:
    """A top-level table as the file's definition has it: a table ([name]) or tables ([[name]])."""
    if shape == "table" and not isinstance(value, dict):
        ctx.fail(name, f"expected a table ([{name}]), got {kind_of(value)}")
    if shape == "tables" and not (isinstance(value, list) and all(isinstance(v, dict) for v in value)):
        ctx.fail(name, f"expected [[{name}]] tables, got {kind_of(value)}")


class CellValidator(Validator):
    """The validator with the taught-pose rules of the cell file."""

    def pose(self, pose_name: str, values, pose_path: str, pose_format: str) -> TaughtPose:
        if not pose_name.strip():
            self.fail(pose_path, "pose name must not be empty")
        count = POSE_FORMATS[pose_format][0]
        if isinstance(values, list) and len(values) != count:
            self.fail(pose_path, f"expected {count} numbers, got {len(values)}{_format_hint(pose_format, len(values))}")
        numbers = self.orientation(
            self.numbers(values, POSE_FORMATS[pose_format][0], pose_path), pose_path, pose_format
        )
        if pose_format == "abb":
            numbers = self.normalise_quaternion(numbers, pose_path)
        bound = TAUGHT_RANGE_MM / (1000.0 if pose_format == "ur" else 1.0)
        if max(abs(v) for v in numbers[:3]) > bound:
            self.fail(pose_path, f"position must be within +-{bound:g} (cell units){metres_hint(pose_format)}")
        return TaughtPose(pose_name, numbers, pose_format)

    def orientation(self, numbers: tuple[float, ...], path: str, pose_format: str) -> tuple[float, ...]:
        """A pose's values with its orientation (after x, y, z) checked: angles within one turn."""
        if pose_format in ORIENTATION_UNITS:
            unit = ORIENTATION_UNITS[pose_format]
            self.angles(numbers[3:], path, unit, "orientation values", metres_hint(pose_format))
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
