"""Run programs in the interpreter on many readings and compare each trace with the reference."""

from __future__ import annotations

import math
import random
import re
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from codegen.camera import CameraModel, SimulatedCamera
from codegen.cell import Cell, Station, TaughtPose
from codegen.controllers import Target, get_target
from codegen.dialects.core.machine import Program
from codegen.dialects.core.values import RunError
from codegen.emit import Emitter
from codegen.poses import native_values
from codegen.reference import (
    INVALID_READING,
    ROTATION_OVER_LIMIT,
    SHIFT_OVER_LIMIT,
    UNKNOWN_STATION,
    FrameCase,
    Reading,
    Trace,
    expected_frame_trace,
    expected_trace,
    frame_offset,
    halt_message,
    wrap_deg,
)
from codegen.vision_pc import VisionPC

# Tolerances from the numeric model (issue 4): a float32 controller over a +-2,000 mm workspace
# stores positions with a step of 1.2e-4 mm and angles with 1e-7 rad; a handful of such roundings
# through the correction stays far below these bounds, a wrong formula far above them.
TOLERANCES = {"float32": (0.005, 0.001), "float64": (1e-9, 1e-9)}  # mm, deg
NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?|(?<!\w)[-+]?(?:nan|inf)\b")


@dataclass(frozen=True)
class Case:
    category: str
    reading: Reading | FrameCase  # point mode: the camera's reading; frame mode: where the mark really is


@dataclass
class TargetReport:
    target: str
    files: list[str]
    cases: int = 0
    mismatches: int = 0
    halts: int = 0
    boundary: int = 0
    moves: int = 0
    pos_errors: list[float] = field(default_factory=list)
    rot_errors: list[float] = field(default_factory=list)
    first_mismatches: list[str] = field(default_factory=list)
    seconds: float = 0.0
    categories: dict[str, int] = field(default_factory=dict)
    photos: list[int] = field(default_factory=list)  # frame mode: photos to converge, per converged case
    frame_errors_mm: list[float] = field(default_factory=list)  # frame mode: |final frame - true frame|
    frame_errors_deg: list[float] = field(default_factory=list)

    def summary(self) -> dict:
        def stats(values):
            if not values:
                return {"max": 0.0, "p99": 0.0}
            arr = np.array(values)
            return {"max": float(arr.max()), "p99": float(np.percentile(arr, 99))}

        return {
            "target": self.target,
            "files": self.files,
            "cases": self.cases,
            "categories": self.categories,
            "mismatches": self.mismatches,
            "halts": self.halts,
            "boundary_cases": self.boundary,
            "moves_compared": self.moves,
            "position_error_mm": stats(self.pos_errors),
            "orientation_error_deg": stats(self.rot_errors),
            "seconds": self.seconds,
            "cases_per_second": self.cases / self.seconds if self.seconds else None,
            "frame": {
                "converged_cases": len(self.photos),
                "photos_mean": float(np.mean(self.photos)) if self.photos else None,
                "photos_max": max(self.photos) if self.photos else None,
                "photos_histogram": {str(k): self.photos.count(k) for k in sorted(set(self.photos))},
                "final_frame_error_mm": stats(self.frame_errors_mm),
                "final_frame_error_deg": stats(self.frame_errors_deg),
            },
            "first_mismatches": self.first_mismatches,
        }


# --- programs --------------------------------------------------------------------------------


def load_program(target: Target, text: str, filename: str, dat_text: str | None = None) -> Program:
    try:
        return _load_program(target, text, filename, dat_text)
    except RecursionError:
        raise RunError(f"{filename}: statements or expressions nested too deeply to run here") from None


def _load_program(target: Target, text: str, filename: str, dat_text: str | None = None) -> Program:
    if target.dialect == "urscript":
        from codegen.dialects.urscript.interpreter import load
    elif target.dialect == "krl":
        from codegen.dialects.krl.interpreter import load as load_krl

        return load_krl(text, filename, dat_text)
    elif target.dialect == "rapid":
        from codegen.dialects.rapid.interpreter import load
    elif target.dialect == "dtrans":
        from codegen.dialects.dtrans.interpreter import load
    else:
        raise ValueError(f"no interpreter for dialect {target.dialect}")
    return load(text, filename)


def load_program_file(target: Target, path: Path) -> Program:
    """A program file on disk (a KRL .src finds its .dat beside it)."""
    return file_source(target.name, path).load()


def fresh_programs(cell: Cell, targets: list[str]) -> dict[str, tuple[Program, list[str]]]:
    """Fresh output of the cell, parsed: target -> (program, file names)."""
    return {s.target: (s.load(), list(s.files)) for s in fresh_sources(cell, targets)}


def target_of_file(path: Path) -> str:
    for name in ("ur", "kuka", "abb", "dtrans"):
        suffixes = {"." + f.rsplit(".", 1)[1] for f in get_target(name).files}
        if path.suffix.lower() in suffixes:
            return name
    raise ValueError(f"{path}: cannot tell the target from the suffix; use --target")


def inputs_for(target: Target, reading: Reading | FrameCase) -> dict:
    names = target.facts["program"]["inputs"]
    if isinstance(reading, FrameCase):
        return {names["station"]: reading.station_id}
    return {
        names["station"]: reading.station_id,
        names["x"]: reading.x,
        names["y"]: reading.y,
        names["theta"]: reading.theta,
    }


def controller_setup(cell: Cell, target: Target, reading: Reading | FrameCase) -> dict:
    """What the controller already holds: a KUKA frame-mode station's measured base BASE_DATA[n]."""
    if target.name != "kuka" or not isinstance(reading, FrameCase):
        return {}
    station = cell.station_by_id(reading.station_id)
    if station is None or station.base_data is None:
        return {}
    return {f"BASE_DATA[{station.base_data}]": native_values(station.frame.values, station.frame.pose_format, "xyzabc")}


def camera_for(cell: Cell, reading: Reading | FrameCase) -> SimulatedCamera | None:
    """A fresh simulated camera for a frame-mode case (the same noise sequence for every run)."""
    if not isinstance(reading, FrameCase):
        return None
    station = cell.station_by_id(reading.station_id)
    base2frame0 = station.frame.matrix()
    base2mark = base2frame0 @ frame_offset(reading.dx, reading.dy, reading.alpha)
    return SimulatedCamera(
        reading.camera, cell.handeye, cell.angle_sign, base2frame0, station.photo.matrix(), base2mark
    )


# --- cases -----------------------------------------------------------------------------------


def edge_cell(cell: Cell) -> Cell:
    """The cell plus one station whose taught poses sit on the conventions' edges."""
    edge_poses_xyzabc = {
        "yaw_wraps_plus": (520.0, 80.0, 310.0, 179.99, 12.0, 171.0),
        "yaw_wraps_minus": (530.0, 60.0, 300.0, -179.99, -8.0, -169.0),
        "b_plus_90": (540.0, 40.0, 320.0, 30.0, 90.0, 0.0),
        "b_minus_90": (510.0, 90.0, 330.0, -45.0, -89.9999, 20.0),
        "rotvec_pi": (500.0, 100.0, 300.0, 0.0, 0.0, 180.0),
        "rotvec_near_pi": (505.0, 95.0, 305.0, 0.002, 0.001, 179.998),
    }
    poses = tuple(
        TaughtPose(name, native_values(values, "xyzabc", cell.pose_format), cell.pose_format)
        for name, values in edge_poses_xyzabc.items()
    )
    new_id = max(s.id for s in cell.stations) + 1
    if new_id > 32767:
        return cell
    station = Station(new_id, "verify_edge_poses", (300.0, 200.0, 179.5), poses)
    return replace(cell, stations=(*cell.stations, station))


def _wrap_camera(theta: float) -> float:
    return wrap_deg(theta)


def build_cases(cell: Cell, count: int, seed: int) -> list[Case]:
    rng = random.Random(seed)
    limits = cell.limits
    shift, rot = limits.max_shift_mm, limits.max_rotation_deg
    cases: list[Case] = []
    for station in cell.stations:
        if station.mode == "frame":
            cases.extend(frame_cases(cell, station, count, rng))
            continue
        tx, ty, t_theta = station.mark

        def reading(dx, dy, dtheta, station=station, tx=tx, ty=ty, t_theta=t_theta):
            return Reading(station.id, tx + dx, ty + dy, _wrap_camera(t_theta + dtheta))

        for _ in range(count):
            r = shift * math.sqrt(rng.random())
            a = rng.uniform(-math.pi, math.pi)
            cases.append(Case("random", reading(r * math.cos(a), r * math.sin(a), rng.uniform(-rot, rot))))
        cases.append(Case("zero_shift", Reading(station.id, tx, ty, t_theta)))
        for sx, sy in ((1, 0), (-1, 0), (0, 1), (0, -1), (0.6, 0.8)):
            cases.append(Case("at_shift_limit", reading(sx * shift, sy * shift, 0.0)))
            cases.append(Case("inside_shift_limit", reading(sx * (shift - 1e-3), sy * (shift - 1e-3), 0.0)))
            cases.append(Case("beyond_shift_limit", reading(sx * (shift + 1e-3), sy * (shift + 1e-3), 0.0)))
        for sign in (1, -1):
            cases.append(Case("phi_at_limit", reading(0.0, 0.0, sign * rot)))
            cases.append(Case("phi_at_limit_with_shift", reading(0.3 * shift, -0.4 * shift, sign * rot)))
            cases.append(Case("inside_rotation_limit", reading(0.0, 0.0, sign * (rot - 1e-3))))
            cases.append(Case("beyond_rotation_limit", reading(0.0, 0.0, sign * (rot + 1e-3))))
        cases.append(Case("far_beyond", reading(5 * shift, 0.0, 0.0)))
        cases.append(Case("far_beyond", reading(0.0, 0.0, min(179.0, 5 * rot))))
        for bad in (
            (math.nan, ty, t_theta),
            (tx, math.inf, t_theta),
            (tx, ty, math.nan),
            (tx, ty, -math.inf),
            (-math.inf, ty, t_theta),
            (2e5, ty, t_theta),
            (tx, -2e5, t_theta),
            (tx, ty, 400.0),
        ):
            cases.append(Case("invalid_reading", Reading(station.id, *bad)))
    known = {s.id for s in cell.stations}
    first = cell.stations[0]
    for station_id in (0, -1, max(known) + 1, 32767, 99999):
        if station_id not in known:
            cases.append(Case("unknown_station", Reading(station_id, *first.mark)))
    return cases


def frame_cases(cell: Cell, station: Station, count: int, rng: random.Random) -> list[Case]:
    """Where the mark really is (within 0.9 of the limits) and how the camera errs."""
    shift, rot = cell.limits.max_shift_mm, cell.limits.max_rotation_deg

    def moved(camera: CameraModel, category: str, fraction: float = 0.9) -> Case:
        r = fraction * shift * math.sqrt(rng.random())
        a = rng.uniform(-math.pi, math.pi)
        return Case(
            category,
            FrameCase(
                station.id, r * math.cos(a), r * math.sin(a), rng.uniform(-fraction * rot, fraction * rot), camera
            ),
        )

    out = []
    kinds = [
        ("frame_exact_camera", lambda i: CameraModel()),
        ("frame_noise", lambda i: CameraModel(noise_px=0.1, noise_deg=0.005, seed=i)),
        ("frame_handeye_scale_3pct", lambda i: CameraModel(scale_error=rng.choice((0.03, -0.03)), seed=i)),
        ("frame_handeye_rotation_2deg", lambda i: CameraModel(rotation_error_deg=rng.choice((2.0, -2.0)), seed=i)),
    ]
    for i in range(count):
        category, camera = kinds[i % len(kinds)]
        out.append(moved(camera(i), category))
    out.append(Case("frame_zero_shift", FrameCase(station.id, 0.0, 0.0, 0.0, CameraModel())))
    for i in range(4):
        out.append(moved(CameraModel(rotation_error_deg=80.0), "frame_camera_diverges"))
        out.append(moved(CameraModel(scale_error=9.0), "frame_camera_too_weak"))
        out.append(moved(CameraModel(fault_at_photo=2), "frame_camera_fault"))
        out.append(Case("frame_beyond_limit", FrameCase(station.id, 1.05 * shift, 0.0, 0.0, CameraModel())))
        out.append(
            Case(
                "frame_beyond_limit",
                FrameCase(station.id, 0.0, 0.0, (1.05 + i) * rot / 1.05 if i < 2 else -1.05 * rot, CameraModel()),
            )
        )
    return out


# --- comparison ------------------------------------------------------------------------------


def _ulp32(value: float) -> float:
    return float(np.spacing(np.float32(abs(value))))


def accepted_traces(cell: Cell, reading: Reading) -> tuple[list[Trace], bool]:
    """The reference trace, plus the other side of a limit when the reading is within float32
    resolution of it (a float32 controller may decide either way there)."""
    if isinstance(reading, FrameCase):
        return accepted_frame_traces(cell, reading)
    reference = expected_trace(cell, reading)
    station = cell.station_by_id(reading.station_id)
    if reference.reason in (UNKNOWN_STATION, INVALID_READING) or station is None:
        return [reference], False
    tx, ty, t_theta = station.mark
    limits = cell.limits
    scale = max(abs(reading.x), abs(reading.y), abs(tx), abs(ty))
    eps_shift = 8 * limits.max_shift_mm * _ulp32(scale) + 4 * _ulp32(limits.max_shift_mm**2)
    margin_shift = limits.max_shift_mm**2 - ((reading.x - tx) ** 2 + (reading.y - ty) ** 2)
    eps_rot = 4 * _ulp32(max(abs(reading.theta), abs(t_theta), 360.0))
    margin_rot = limits.max_rotation_deg - abs(wrap_deg(reading.theta - t_theta))
    shift_options = [margin_shift < 0] if abs(margin_shift) > eps_shift else [False, True]
    rot_options = [margin_rot < 0] if abs(margin_rot) > eps_rot else [False, True]
    if len(shift_options) == 1 and len(rot_options) == 1:
        return [reference], False
    free = expected_trace(cell, reading, enforce_limits=False)
    out = []
    for shift_over in shift_options:
        for rot_over in rot_options:
            if shift_over:
                out.append(replace(free, status="halt", reason=SHIFT_OVER_LIMIT, moves=(), deviation=None))
            elif rot_over:
                out.append(replace(free, status="halt", reason=ROTATION_OVER_LIMIT, moves=(), deviation=None))
            else:
                out.append(free)
    return out, True


def _pose_errors(a: list, b: list) -> tuple[float, float]:
    """Position distance (mm) and rotation angle (deg) between two 4x4 poses given as lists; the
    angle from ||Ra - Rb||_F = 2 sqrt(2) sin(angle / 2), exact for any angle."""
    (a0, a1, a2, _), (b0, b1, b2, _) = a, b
    position = math.dist((a0[3], a1[3], a2[3]), (b0[3], b1[3], b2[3]))
    distance = math.dist(a0[:3] + a1[:3] + a2[:3], b0[:3] + b1[:3] + b2[:3])  # Frobenius norm of Ra - Rb
    return position, math.degrees(2.0 * math.asin(min(1.0, distance / (2.0 * math.sqrt(2.0)))))


FRAME_NUDGE = 0.01  # a float32 residual is within 1 % of the tolerance far beyond its rounding


def accepted_frame_traces(cell: Cell, case: FrameCase) -> tuple[list[Trace], bool]:
    reference = expected_frame_trace(cell, case)
    tol_mm, tol_deg = cell.refine.tolerance_mm, cell.refine.tolerance_deg
    near = any(
        abs(r - tol_mm) <= FRAME_NUDGE * tol_mm or abs(g - tol_deg) <= FRAME_NUDGE * tol_deg
        for r, g in reference.residuals
    )
    if not near:
        return [reference], False
    nudged = [expected_frame_trace(cell, case, FRAME_NUDGE), expected_frame_trace(cell, case, -FRAME_NUDGE)]
    return [reference, *nudged], True


def expected_message(cell: Cell, trace: Trace, reading: Reading, emitter: Emitter) -> str:
    if trace.reason == UNKNOWN_STATION:
        from codegen.render import UNKNOWN_STATION_TEXT

        return emitter.string(UNKNOWN_STATION_TEXT) + str(reading.station_id)
    return emitter.string(halt_message(cell, trace, reading.station_id))


def _log_numbers(messages: list[str]) -> list[float]:
    out = []
    for message in messages:
        if message.startswith(("deviation", "frame")):
            out.extend(float(n) for n in NUMBER.findall(message))
    return out


def compare(cell: Cell, target: Target, reading: Reading, expected: Trace, got, emitter: Emitter):
    """(problem or None, position errors, orientation errors)."""
    pos_tol, rot_tol = TOLERANCES[target.numbers]
    if expected.status == "halt":
        if not got.halted:
            return f"expected a halt ({expected.reason}), program did not halt ({len(got.moves)} moves)", [], []
        want = expected_message(cell, expected, reading, emitter)
        if got.halt_message != want:
            return f"halt message {got.halt_message!r}, expected {want!r}", [], []
    elif got.halted:
        return f"unexpected halt: {got.halt_message!r}", [], []
    if len(got.moves) != len(expected.moves):
        return f"{len(got.moves)} moves, expected {len(expected.moves)}", [], []
    pos_errors, rot_errors = [], []
    for i, (g, e) in enumerate(zip(got.moves, expected.moves, strict=True)):
        if g.kind != e.kind:
            return f"move {i + 1} ({e.pose_name}) is {g.kind}, expected {e.kind}", [], []
        pos, rot = _pose_errors(g.base2tcp.tolist(), e.base2tcp.tolist())
        pos_errors.append(pos)
        rot_errors.append(rot)
        if not pos <= pos_tol or not rot <= rot_tol:
            return (
                (
                    f"move {i + 1} ({e.pose_name}, line {g.line}): position error {pos:.6f} mm, "
                    f"orientation error {rot:.6f} deg (tolerance {pos_tol} mm, {rot_tol} deg)"
                ),
                pos_errors,
                rot_errors,
            )
    if expected.status == "halt":
        return None, pos_errors, rot_errors
    numbers = _log_numbers(got.messages)
    want = list(expected.deviation)
    decimals = target.facts["program"].get("log_decimals")
    log_tol = 0.5 * 10.0**-decimals + 1e-3 if decimals is not None else pos_tol
    if len(numbers) != len(want):
        return f"deviation line has {len(numbers)} numbers, expected {len(want)}: {got.messages!r}", [], []
    names = (
        ("station", "dx", "dy", "alpha", "photos")
        if isinstance(reading, FrameCase)
        else ("station", "dx1", "dy1", "dx2", "dy2", "dtheta")
    )
    for name, g, w in zip(names, numbers, want, strict=True):
        if not abs(g - w) <= log_tol:
            return f"deviation {name} = {g}, expected {w:.6f} (tolerance {log_tol})", pos_errors, rot_errors
    return None, pos_errors, rot_errors


def describe_case(reading: Reading | FrameCase) -> str:
    if isinstance(reading, FrameCase):
        return (
            f"station {reading.station_id} mark moved ({reading.dx!r}, {reading.dy!r}, {reading.alpha!r}) "
            f"camera {reading.camera}"
        )
    return f"station {reading.station_id} reading ({reading.x!r}, {reading.y!r}, {reading.theta!r})"


def frame_statistics(report: TargetReport, case: FrameCase, logged: list[float]) -> None:
    """Photos to converge and how far the program's final frame is from where the mark really is."""
    _station, dx, dy, alpha, photos = logged
    report.photos.append(int(photos))
    report.frame_errors_mm.append(math.hypot(dx - case.dx, dy - case.dy))
    report.frame_errors_deg.append(abs(alpha - case.alpha))


def verify(
    cell: Cell,
    targets: list[str],
    programs: dict[str, tuple[Program, list[str]]],
    cases: list[Case],
    progress=None,
    verify_cell: Cell | None = None,
) -> list[TargetReport]:
    """Run every case on every target's program; verify_cell is the cell the programs were made from."""
    model = verify_cell or cell
    expectations = [(case, *accepted_traces(model, case.reading)) for case in cases]
    reports = []
    for name in targets:
        target = get_target(name)
        program, files = programs[name]
        emitter = Emitter(target)
        report = TargetReport(name, files)
        start = time.perf_counter()
        for case, accepted, boundary in expectations:
            report.cases += 1
            report.categories[case.category] = report.categories.get(case.category, 0) + 1
            report.boundary += boundary
            try:
                inputs = inputs_for(target, case.reading) | controller_setup(model, target, case.reading)
                got = program.run(inputs, devices=(VisionPC.for_target(target, camera_for(model, case.reading)),))
            except RunError as exc:
                problem, pos, rot = f"run error: {exc}", [], []
            else:
                problem, pos, rot = None, [], []
                for expected in accepted:
                    problem, pos, rot = compare(model, target, case.reading, expected, got, emitter)
                    if problem is None:
                        report.halts += got.halted
                        if isinstance(case.reading, FrameCase) and not got.halted:
                            frame_statistics(report, case.reading, _log_numbers(got.messages))
                        break
            report.pos_errors.extend(pos)
            report.rot_errors.extend(rot)
            report.moves += len(pos) if problem is None else 0
            if problem is not None:
                report.mismatches += 1
                if len(report.first_mismatches) < 10:
                    report.first_mismatches.append(f"{case.category} {describe_case(case.reading)}: {problem}")
            if progress is not None:
                progress(1)
        report.seconds = time.perf_counter() - start
        reports.append(report)
    return reports


# --- parallel runs --------------------------------------------------------------------------


@dataclass(frozen=True)
class ProgramSource:
    """A program as text (picklable), so that worker processes can parse it themselves."""

    target: str
    text: str
    filename: str
    dat_text: str | None
    files: tuple[str, ...]

    def load(self) -> Program:
        return load_program(get_target(self.target), self.text, self.filename, self.dat_text)


def fresh_sources(cell: Cell, targets: list[str]) -> list[ProgramSource]:
    from codegen.render import render

    files = render(cell, targets)
    out = []
    for name in targets:
        mine = [f for f in files if f.relpath.split("/")[1] == name]
        main = next(f for f in mine if not f.relpath.endswith(".dat"))
        dat = next((f.text for f in mine if f.relpath.endswith(".dat")), None)
        out.append(ProgramSource(name, main.text, f"<fresh>/{main.relpath}", dat, tuple(f.relpath for f in mine)))
    return out


def file_source(target: str, path: Path) -> ProgramSource:
    dat_text, files = None, [str(path)]
    if get_target(target).dialect == "krl":
        dat = path.with_suffix(".dat")
        if dat.exists():
            dat_text = dat.read_text(encoding="utf-8")
            files.append(str(dat))
    return ProgramSource(target, path.read_text(encoding="utf-8"), str(path), dat_text, tuple(files))


_LOADED: dict[ProgramSource, Program] = {}


def _verify_chunk(args) -> list[TargetReport]:
    """One chunk of cases on every source (the reference runs once per case)."""
    cell, verify_cell, sources, cases = args
    programs = {}
    for source in sources:
        if source not in _LOADED:
            _LOADED[source] = source.load()
        programs[source.target] = (_LOADED[source], list(source.files))
    return verify(cell, [s.target for s in sources], programs, cases, verify_cell=verify_cell)


def _merge(parts: list[TargetReport]) -> TargetReport:
    out = TargetReport(parts[0].target, parts[0].files)
    for part in parts:
        out.cases += part.cases
        out.mismatches += part.mismatches
        out.halts += part.halts
        out.boundary += part.boundary
        out.moves += part.moves
        out.pos_errors.extend(part.pos_errors)
        out.rot_errors.extend(part.rot_errors)
        out.first_mismatches.extend(part.first_mismatches[: 10 - len(out.first_mismatches)])
        out.seconds += part.seconds
        out.photos.extend(part.photos)
        out.frame_errors_mm.extend(part.frame_errors_mm)
        out.frame_errors_deg.extend(part.frame_errors_deg)
        for key, count in part.categories.items():
            out.categories[key] = out.categories.get(key, 0) + count
    return out


def run_verify(
    cell: Cell,
    sources: list[ProgramSource],
    cases: list[Case],
    jobs: int = 1,
    progress=None,
    verify_cell: Cell | None = None,
) -> list[TargetReport]:
    """Verify every source on every case, in `jobs` processes; `seconds` is the time spent running
    one dialect's cases (summed over workers), so cases/seconds is the per-dialect speed."""
    chunk = max(1, -(-len(cases) // max(4, 2 * jobs)))
    tasks = [(cell, verify_cell, sources, cases[i : i + chunk]) for i in range(0, len(cases), chunk)]
    parts: dict[str, list[TargetReport]] = {source.target: [] for source in sources}

    def collect(reports: list[TargetReport]) -> None:
        for part in reports:
            parts[part.target].append(part)
            if progress is not None:
                progress(part.cases)

    if jobs <= 1:
        for task in tasks:
            collect(_verify_chunk(task))
    else:
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        context = multiprocessing.get_context("fork") if "fork" in multiprocessing.get_all_start_methods() else None
        with ProcessPoolExecutor(max_workers=jobs, mp_context=context) as pool:
            for reports in pool.map(_verify_chunk, tasks):
                collect(reports)
    return [_merge(parts[source.target]) for source in sources]
