"""Render a cell for each target through Jinja templates, validate, and write atomically."""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from importlib.resources import files
from pathlib import Path

from codegen import __version__, derived
from codegen.cell import Cell
from codegen.controllers import Target, get_target
from codegen.emit import EmitError, Emitter
from codegen.poses import FORMAT_DECIMALS, native_values
from codegen.reference import (
    INVALID_READING,
    NOT_CONVERGED,
    PIXEL_RANGE,
    ROTATION_OVER_LIMIT,
    SHIFT_OVER_LIMIT,
    Trace,
    halt_message,
)

TEMPLATES_DIR = Path(str(files("codegen.templates")))

# Guard codes shared by every program: 0 ok, then the halt reasons in the order they are checked.
GUARD_CODES = {INVALID_READING: 1, SHIFT_OVER_LIMIT: 2, ROTATION_OVER_LIMIT: 3}
MARK_DECIMALS = 6
UNKNOWN_STATION_TEXT = "unknown station id "


@dataclass(frozen=True)
class RenderedFile:
    relpath: str  # <cell>/<target>/<file>
    text: str


def _env():
    import jinja2  # imported where used: `codegen correct` must not pay for it

    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(TEMPLATES_DIR)),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
    )


def station_messages(cell: Cell, station, emitter: Emitter) -> dict[str, str]:
    """The halt message for each reason, as the target's string literal body."""
    reasons = (*GUARD_CODES, NOT_CONVERGED)
    return {
        reason: emitter.string(halt_message(cell, Trace("halt", reason, station), station.id)) for reason in reasons
    }


def _pose_numbers(pose, fmt: str, emitter: Emitter) -> list[str]:
    values = native_values(pose.values, pose.pose_format, fmt)
    return [emitter.number(v, d) for v, d in zip(values, FORMAT_DECIMALS[fmt], strict=True)]


def _level(pose) -> bool:
    """A frame whose x-y plane is the base x-y plane (only Rz): the dtrans dialect can compose it."""
    return abs(pose.matrix()[2, 2] - 1.0) < 1e-12


def _station_context(cell: Cell, station, target: Target, emitter: Emitter) -> dict:
    origin = f"station[{station.id}] {station.name!r}"
    fmt = target.pose_format
    poses = [
        {
            "name": emitter.comment(pose.name),
            "ident": emitter.identifier(f"p{station.id}_", pose.name, f"{origin} pose {pose.name!r}"),
            "numbers": _pose_numbers(pose, fmt, emitter),
            "motion": "joint" if i == 0 else "linear",
        }
        for i, pose in enumerate(station.poses)
    ]
    frame = photo = None
    if station.mode == "frame":
        if target.name == "dtrans" and not _level(station.frame):
            raise EmitError(
                f"dtrans: {origin} frame must be level (b = c = 0): the dialect composes poses only by "
                "Decompose/Trans and yaw addition"
            )
        frame = {
            "ident": emitter.identifier(f"f{station.id}_", station.name, f"{origin} frame"),
            "numbers": _pose_numbers(station.frame, fmt, emitter),
        }
        photo = {
            "ident": emitter.identifier(f"c{station.id}_", "photo", f"{origin} photo pose"),
            "numbers": _pose_numbers(station.photo, fmt, emitter),
        }
    return {
        "mode": station.mode,
        "frame": frame,
        "base_data": station.base_data,
        "photo": photo,
        "id": station.id,
        "name": emitter.comment(station.name),
        "ident": emitter.identifier("st_", station.name, origin),
        "mark_ident": emitter.identifier(f"m{station.id}_", station.name, f"{origin} mark"),
        "mark": [emitter.number(v, MARK_DECIMALS) for v in station.mark],
        "poses": poses,
        "work": poses[-1],
        "messages": station_messages(cell, station, emitter),
    }


def context(cell: Cell, target: Target) -> dict:
    emitter = Emitter(target)
    number = emitter.number
    stations = [_station_context(cell, station, target, emitter) for station in cell.stations]
    return {
        "version": __version__,
        "cell": {
            "name": cell.name,
            "ident": emitter.identifier("", cell.name, "cell name"),
            "comment": emitter.comment(cell.name),
            "source": emitter.comment(Path(cell.source).name),
            "sha256": cell.sha256,
            "angle_sign": str(cell.angle_sign),
            "max_shift_sq": number(cell.limits.max_shift_mm**2, 6),
            "max_shift": number(cell.limits.max_shift_mm, 6),
            "max_rotation": number(cell.limits.max_rotation_deg, 6),
            "max_shift_text": f"{cell.limits.max_shift_mm:g}",
            "max_rotation_text": f"{cell.limits.max_rotation_deg:g}",
        },
        "codes": GUARD_CODES,
        "stations": stations,
        "has_point": any(st["mode"] == "point" for st in stations),
        "has_frame": any(st["mode"] == "frame" for st in stations),
        "frame": derived.printed(target.dialect, "frame"),
        "point": derived.printed(target.dialect, "point"),
        "refine": derived.printed(target.dialect, "refine"),
        "handeye": None if cell.handeye is None else [number(v, 9) for row in cell.handeye for v in row],
        "tolerance": {
            "mm_sq": number(cell.refine.tolerance_mm**2, 9),
            "deg": number(cell.refine.tolerance_deg, 6),
            "mm_text": f"{cell.refine.tolerance_mm:g}",
            "deg_text": f"{cell.refine.tolerance_deg:g}",
            "photos": str(cell.refine.max_iterations),
        },
        "pixel_range": number(PIXEL_RANGE, 1),
        "unknown_station_text": emitter.string(UNKNOWN_STATION_TEXT),
        "target": target,
    }


def cell_dir(cell: Cell) -> str:
    """The folder of a cell under generated/: its name in [a-z0-9_] (target-independent)."""
    return Emitter(get_target("ur")).identifier("", cell.name, "cell name").lower()


def output_names(cell: Cell, target: Target) -> list[str]:
    """File names; the program name inside must match them (KRL, RAPID), so both come from one identifier."""
    ident = Emitter(target).identifier("", cell.name, "cell name")
    return [name.format(cell=ident.lower()) for name in target.files]


def render(cell: Cell, targets: list[str] | None = None) -> list[RenderedFile]:
    """Every file of every requested target, rendered in memory (nothing written)."""
    env = _env()
    out = []
    for name in targets or list(cell.targets):
        target = get_target(name)
        ctx = context(cell, target)
        for template_name, file_name in zip(target.files, output_names(cell, target), strict=True):
            suffix = template_name.rsplit(".", 1)[1]
            text = env.get_template(f"{name}/program.{suffix}.j2").render(ctx)
            out.append(RenderedFile(f"{cell_dir(cell)}/{name}/{file_name}", text))
    return out


def write_atomic(files: list[RenderedFile], out_dir: Path) -> list[Path]:
    """Write every file to a temporary name beside its destination, then rename them all."""
    staged: list[tuple[Path, Path]] = []
    try:
        for f in files:
            dest = out_dir / f.relpath
            dest.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(prefix=f".{dest.name}.", suffix=".tmp", dir=dest.parent)
            staged.append((Path(tmp), dest))
            try:
                handle = os.fdopen(fd, "w", encoding="utf-8", newline="\n")
            except BaseException:
                os.close(fd)
                raise
            with handle:
                handle.write(f.text)
    except BaseException:
        for tmp, _ in staged:
            tmp.unlink(missing_ok=True)
        raise
    for tmp, dest in staged:
        os.replace(tmp, dest)
    return [dest for _, dest in staged]
