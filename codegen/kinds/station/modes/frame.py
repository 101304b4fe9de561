"""The frame mode (source 001): photograph, shift the frame, repeat until the residual is small."""

from __future__ import annotations

import cmath
import math
import random
from dataclasses import dataclass, field, replace
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from codegen import derived
from codegen.controllers import get_target
from codegen.emit import EmitError, owned
from codegen.guard import (
    GUARD_CODES,
    INVALID_READING,
    PIXEL_RANGE,
    ROTATION_OVER_LIMIT,
    SHIFT_OVER_LIMIT,
    UNKNOWN_STATION,
    pixels_in_range,
)
from codegen.kinds.station.frame.keys import KEYS, REFINE
from codegen.kinds.station.mode import StationMode
from codegen.kinds.station.section import section_of, station_label
from codegen.model.loader import Loader, build
from codegen.model.vision import PHOTO
from codegen.poses import POSE_FORMATS, concat, matrix_from_rotation_translation, native_values, planar_motions, rotz
from codegen.protocol import Figures
from codegen.reference import JOINT, ExpectedTrace, Move, path_moves

if TYPE_CHECKING:
    from codegen.kinds.station.cases import Case
    from codegen.sim.camera import CameraModel, SimulatedCamera

NOT_CONVERGED = "not_converged"  # a halt reason of this mode: the residual stayed over tolerance
FRAME_NUDGE = 0.01  # a float32 residual is within 1 % of the tolerance far beyond its rounding
# A camera finds a mark's centre to about a tenth of a pixel (sub-pixel edge or blob fitting; an assumption, not a
# vendor's figure): a loop whose tolerance is under a few times that noise halts on noise, not on the frame.
SUBPIXEL_NOISE_PX = 0.1
RESOLVED_SIGMAS = 4  # the tolerance this many standard deviations of that noise: a true convergence stops the loop


@dataclass(frozen=True)
class Refine:
    """[cell.refine]: when the refinement loop stops (source 001: 0.02 mm and 0.04 deg)."""

    tolerance_mm: float = REFINE.default("tolerance_mm")
    tolerance_deg: float = REFINE.default("tolerance_deg")
    max_iterations: int = REFINE.default("max_iterations")


@dataclass(frozen=True)
class FrameSpec:
    """The user frame at calibration (base frame; the mark at its origin), the photo pose in that
    frame, and optionally the controller's numbered base holding the same frame."""

    frame: object  # codegen.model.cell.TaughtPose
    photo: object  # codegen.model.cell.TaughtPose
    base_data: int | None = None


@dataclass(frozen=True)
class FrameCase:
    """Where the station's mark really is, relative to its calibration frame, and the camera."""

    station_id: int
    dx: float  # mm, in the calibration frame's axes
    dy: float
    alpha: float  # deg
    camera: CameraModel


@dataclass(frozen=True)
class FrameDetail:
    iterations: int  # photos taken
    residuals: tuple[tuple[float, float], ...] = ()  # every photo's residual: |res| mm, |gamma| deg
    final_residual: tuple[float, float] | None = None
    frame2base: np.ndarray | None = None  # the converged frame


@lru_cache(maxsize=16)
def _singular_values(pixel_to_mm) -> np.ndarray:
    """mm per pixel along the map's two principal directions (once per cell, not per case)."""
    return np.linalg.svd(np.array(pixel_to_mm)[:, :2], compute_uv=False)


def frame_offset(dx: float, dy: float, alpha_deg: float) -> np.ndarray:
    """Trans(dx, dy, 0) . Rz(alpha): a frame moved in its own x-y plane."""
    return matrix_from_rotation_translation(rotz(math.radians(alpha_deg)), (dx, dy, 0.0))


def camera_for(cell, case: FrameCase) -> SimulatedCamera:
    """A fresh simulated camera for one case (the same noise sequence for every run)."""
    spec = section_of(cell).station_by_id(case.station_id).spec
    calib2base = spec.frame.matrix()
    mark2base = concat(frame_offset(case.dx, case.dy, case.alpha), calib2base)
    from codegen.sim.camera import SimulatedCamera  # verify's: a cell loads without the simulator

    return SimulatedCamera(case.camera, section_of(cell).handeye, calib2base, spec.photo.matrix(), mark2base)


def expected_frame_trace(cell, case: FrameCase, nudge: float = 0.0) -> ExpectedTrace:
    """Source 001's loop in float64 against the simulated camera, with the update proven in
    derivation.frame_update. nudge scales the tolerances by (1 + nudge): a float32 controller may
    decide the other way when a residual sits on the tolerance."""
    station = section_of(cell).station_by_id(case.station_id)
    if station is None:
        return ExpectedTrace("halt", UNKNOWN_STATION)
    spec = station.spec
    calib2base, photo2frame = spec.frame.matrix(), spec.photo.matrix()
    camera = camera_for(cell, case)
    section = section_of(cell)
    handeye = np.array(section.handeye)
    refine, limits = section.settings[FrameMode.name], section.limits
    tol_mm, tol_deg = refine.tolerance_mm * (1 + nudge), refine.tolerance_deg * (1 + nudge)
    dx = dy = alpha = 0.0
    moves: list[Move] = []
    photos, residual = 0, None
    residuals: list[tuple[float, float]] = []

    def halt(reason: str) -> ExpectedTrace:
        detail = FrameDetail(photos, tuple(residuals), residual)
        return ExpectedTrace("halt", reason, station, tuple(moves), detail=detail)

    while True:
        if photos >= refine.max_iterations:
            return halt(NOT_CONVERGED)
        tcp2base = concat(photo2frame, frame_offset(dx, dy, alpha), calib2base)
        moves.append(
            Move(
                kind=JOINT,
                pose_name="photo",
                tcp2base=tcp2base,
                exact=True,
                speed_mm_s=cell.motion.speed_mm_s,
                joint_percent=cell.motion.joint_speed_percent,
            )
        )
        photos += 1
        u, v, angle = camera.photo(tcp2base)
        if not pixels_in_range(u, v, angle):
            residual = None
            return halt(INVALID_READING)
        res_x, res_y = handeye @ np.array([u, v, 1.0])
        gamma = section_of(cell).angle_sign * angle
        residual = (math.hypot(res_x, res_y), abs(gamma))
        residuals.append(residual)
        if res_x**2 + res_y**2 < tol_mm**2 and abs(gamma) < tol_deg:
            break
        c, s_ = math.cos(math.radians(alpha)), math.sin(math.radians(alpha))
        dx, dy, alpha = dx + c * res_x - s_ * res_y, dy + s_ * res_x + c * res_y, alpha + gamma
        if dx**2 + dy**2 > limits.max_shift_mm**2:
            residual = None
            return halt(SHIFT_OVER_LIMIT)
        if abs(alpha) > limits.max_rotation_deg:
            residual = None
            return halt(ROTATION_OVER_LIMIT)
    frame2base = concat(frame_offset(dx, dy, alpha), calib2base)
    start = len(moves)  # the photos come first
    moves.extend(path_moves(cell, station, frame2base))
    deviation = (float(station.id), dx, dy, alpha, float(photos))
    detail = FrameDetail(photos, tuple(residuals), residual, frame2base)
    return ExpectedTrace("ok", None, station, tuple(moves), deviation, detail, path_start=start)


@dataclass
class FrameStats(Figures):
    """Photos to converge and how far the program's final frame is from where the mark really is."""

    photos: list[int] = field(default_factory=list)
    errors_mm: list[float] = field(default_factory=list)
    errors_deg: list[float] = field(default_factory=list)

    def count(self, case: FrameCase, judged: list[float]) -> None:
        """A passing case's logged numbers."""
        _station, dx, dy, alpha, photos = judged
        self.photos.append(int(photos))
        self.errors_mm.append(math.hypot(dx - case.dx, dy - case.dy))
        self.errors_deg.append(abs(alpha - case.alpha))

    def as_json(self) -> dict:
        photos = self.photos
        return {
            "converged_cases": len(photos),
            "photos_mean": float(np.mean(photos)) if photos else None,
            "photos_max": max(photos) if photos else None,
            "photos_histogram": {str(k): photos.count(k) for k in sorted(set(photos))},
            "final_frame_error_mm": _stats(self.errors_mm),
            "final_frame_error_deg": _stats(self.errors_deg),
        }


def _stats(values: list[float]) -> dict:
    if not values:
        return {"max": 0.0, "p99": 0.0}
    arr = np.array(values)
    return {"max": float(arr.max()), "p99": float(np.percentile(arr, 99))}


class FrameMode(StationMode):
    name = "frame"
    reads_pixels = True
    order = 1
    cell_file = KEYS
    model_inputs = frozenset({"angle_sign", "calibration", "derivation"})
    log_prefixes = ("frame",)
    log_names = ("station", "dx", "dy", "alpha", "photos")
    answer_names = {PHOTO: ("u", "v", "angle")}
    figures = FrameStats

    @classmethod
    def station_scene(cls, cell, station) -> list[dict]:
        from codegen.kinds.station.frame.scene import objects  # the page's: a cell loads without it

        return objects(cell, station)

    @classmethod
    def commands(cls) -> list:
        from codegen.kinds.station.frame.commands import calibrate_handeye  # click: the command line's alone

        return [("calibrate", calibrate_handeye)]

    @classmethod
    def parse(cls, ctx, values: dict, path: str) -> FrameSpec:
        return FrameSpec(values["frame"], values["photo"], values["base_data"])

    @classmethod
    def moved(cls, spec: FrameSpec, mm: float) -> FrameSpec:
        frame = spec.frame
        frame2base = frame.matrix().copy()
        frame2base[0, 3] += mm
        values = POSE_FORMATS[frame.pose_format][2](frame2base)
        return replace(spec, frame=replace(frame, values=tuple(values)))

    @classmethod
    def parse_settings(cls, ctx, cell_table: dict) -> Refine:
        return build(Refine, Loader(ctx).table(REFINE, cell_table.get("refine", {}), "cell.refine"))

    @classmethod
    def halt_message(cls, cell, reason: str, station) -> str:
        if reason == NOT_CONVERGED:
            photos = section_of(cell).settings[cls.name].max_iterations
            return f"station {station.name}: frame not converged after {photos} photos"
        return super().halt_message(cell, reason, station)

    @classmethod
    def check_station(cls, ctx, path: str, station, cell) -> None:
        for name in cell.targets:
            base_data = get_target(name).program.get("base_data")
            if base_data and station.spec.base_data is not None and station.spec.base_data > base_data["max"]:
                ctx.fail(
                    f"{path}.base_data",
                    f"target {name} stores bases 1..{base_data['max']}, got {station.spec.base_data}",
                )
        if section_of(cell).handeye is None:
            ctx.fail(
                f"{path}.mode",
                "frame mode reads the camera in pixels and needs [cell.camera.handeye] "
                "(write it with `codegen calibrate handeye POINTS.csv --write CELL`)",
            )
        refine = section_of(cell).settings[cls.name]
        least_mm = RESOLVED_SIGMAS * SUBPIXEL_NOISE_PX * float(_singular_values(section_of(cell).handeye)[0])
        if refine.tolerance_mm < least_mm:
            ctx.fail(
                "cell.refine.tolerance_mm",
                f"{refine.tolerance_mm:g} mm is finer than the camera resolves: a pixel is "
                f"{least_mm / (RESOLVED_SIGMAS * SUBPIXEL_NOISE_PX):.4f} mm here and a mark's centre is found to about "
                f"{SUBPIXEL_NOISE_PX} px, so the loop would stop on noise or not at all; set "
                f"[cell.refine] tolerance_mm = {math.ceil(least_mm * 1e4) / 1e4:.4f} or more ({RESOLVED_SIGMAS} x "
                f"{SUBPIXEL_NOISE_PX} px, rounded up)",
            )

    @classmethod
    def arm_poses(cls, cell, station) -> list[tuple[str, np.ndarray, str]]:
        # the photo pose first (a joint move, repeated while the frame is refined), then the path
        calib2base = station.spec.frame.matrix()
        photo = ("photo", concat(station.spec.photo.matrix(), calib2base), "joint")
        path = [(name, concat(p2f, calib2base), motion) for name, p2f, motion in super().arm_poses(cell, station)]
        return [photo, *path]

    @classmethod
    def region(cls, cell, station, offsets) -> np.ndarray:
        # the frame moved in its own x-y plane: calib2base . frame_offset . pose2frame
        calib2base = station.spec.frame.matrix()
        frames = np.einsum("ij,njk->nik", calib2base, planar_motions(offsets))
        poses = np.array([station.spec.photo.matrix(), *(p.matrix() for p in station.path)])
        return np.einsum("nij,mjk->nmik", frames, poses)

    @classmethod
    def cell_context(cls, cell, target, emitter) -> dict:
        number, section = emitter.number, section_of(cell)
        refine, handeye = section.settings[cls.name], section.handeye
        return {
            "refine": owned(derived.printed(target.dialect, "refine")),
            "handeye": None if handeye is None else [number(v, 9) for row in handeye for v in row],
            "tolerance": {
                "mm_sq": number(refine.tolerance_mm**2, 9),
                "deg": number(refine.tolerance_deg, 6),
                "mm_text": emitter.figure(refine.tolerance_mm),
                "deg_text": emitter.figure(refine.tolerance_deg),
                "photos": refine.max_iterations,
            },
            "pixel_range": number(PIXEL_RANGE, 1),
        }

    @classmethod
    def station_context(cls, cell, station, target, emitter) -> dict:
        origin = station_label(cell, station)
        spec = station.spec
        if target.program.get("level_frames_only") and abs(spec.frame.matrix()[2, 2] - 1.0) >= 1e-12:
            raise EmitError(
                f"{target.name}: {origin} frame must be level (b = c = 0): the target composes frames only "
                "in the x-y plane (level_frames_only)"
            )
        base_data = target.program.get("base_data")
        base_data_name = base_data["name"].format(n=spec.base_data) if base_data and spec.base_data else None
        return {
            "frame": {
                "ident": emitter.identifier(f"f{station.id}_", station.name, f"{origin} frame"),
                "numbers": emitter.pose(spec.frame),
            },
            "photo": {
                "ident": emitter.identifier(f"c{station.id}_", "photo", f"{origin} photo pose"),
                "numbers": emitter.pose(spec.photo),
            },
            "wobj": emitter.identifier(f"w{station.id}_", station.name, f"{origin} work object"),
            "base_data": spec.base_data,
            "base_data_name": owned(base_data_name),
            "messages": {
                reason: emitter.string(cls.fitted_message(cell, reason, station, target.string_max))
                for reason in (*GUARD_CODES, NOT_CONVERGED)
            },
        }

    @classmethod
    def cases(cls, cell, station, count: int, rng: random.Random) -> list[Case]:
        """Where the mark really is (within 0.9 of the limits) and how the camera errs."""
        from codegen.kinds.station.cases import Case  # verify's: a cell loads without the simulator
        from codegen.sim.camera import CameraModel

        limits = section_of(cell).limits
        shift, rot = limits.max_shift_mm, limits.max_rotation_deg

        def moved(camera: CameraModel, category: str, fraction: float = 0.9) -> Case:
            r = fraction * shift * math.sqrt(rng.random())
            a = rng.uniform(-math.pi, math.pi)
            alpha = rng.uniform(-fraction * rot, fraction * rot)
            return Case(category, FrameCase(station.id, r * math.cos(a), r * math.sin(a), alpha, camera))

        out = []
        cameras = [
            ("frame_exact_camera", lambda i: CameraModel()),
            ("frame_noise", lambda i: CameraModel(noise_px=SUBPIXEL_NOISE_PX, noise_deg=0.005, seed=i)),
            ("frame_handeye_scale_3pct", lambda i: CameraModel(scale_error=rng.choice((0.03, -0.03)), seed=i)),
            (
                "frame_handeye_rotation_2deg",
                lambda i: CameraModel(rotation_error_deg=rng.choice((2.0, -2.0)), seed=i),
            ),
        ]
        for i in range(count):
            category, camera = cameras[i % len(cameras)]
            out.append(moved(camera(i), category))
        out.append(cls.nominal_case(cell, station))
        for i in range(4):
            out.append(moved(CameraModel(rotation_error_deg=80.0), "frame_camera_diverges"))
            out.append(moved(CameraModel(scale_error=9.0), "frame_camera_too_weak"))
            out.append(moved(CameraModel(fault_at_photo=2), "frame_camera_fault"))
            out.append(Case("frame_beyond_limit", FrameCase(station.id, 1.05 * shift, 0.0, 0.0, CameraModel())))
            alpha = (1.05 + i) * rot / 1.05 if i < 2 else -1.05 * rot
            out.append(Case("frame_beyond_limit", FrameCase(station.id, 0.0, 0.0, alpha, CameraModel())))
        return out

    @classmethod
    def nominal_case(cls, cell, station) -> Case:
        from codegen.kinds.station.cases import Case  # verify's: a cell loads without the simulator
        from codegen.sim.camera import CameraModel

        return Case("frame_zero_shift", FrameCase(station.id, 0.0, 0.0, 0.0, CameraModel()))

    @classmethod
    def accepted(cls, cell, case: FrameCase) -> tuple[list[ExpectedTrace], bool]:
        reference = expected_frame_trace(cell, case)
        refine = section_of(cell).settings[cls.name]
        tol_mm, tol_deg = refine.tolerance_mm, refine.tolerance_deg
        residuals = reference.detail.residuals if reference.detail else ()
        near = any(
            abs(r - tol_mm) <= FRAME_NUDGE * tol_mm or abs(g - tol_deg) <= FRAME_NUDGE * tol_deg for r, g in residuals
        )
        if not near:
            return [reference], False
        nudged = [expected_frame_trace(cell, case, FRAME_NUDGE), expected_frame_trace(cell, case, -FRAME_NUDGE)]
        return [reference, *nudged], True

    @classmethod
    def truth_problem(cls, cell, case: FrameCase, reference: ExpectedTrace) -> str | None:
        """A camera that measures well (its hand-eye error contracts the residual by q <= 1/2 per photo,
        so the loop needs far fewer photos than allowed) and a mark within the limits: a correct cell
        converges, and onto the true mark. Its frame may be off by what the stop rule lets through:
        the tolerance scaled by the camera's scale error and its map's anisotropy, plus four standard
        deviations of the noise. A reference that does not (a cell whose angle_sign contradicts its
        camera's image) is a mismatch for every target."""
        section = section_of(cell)
        camera, refine, limits = case.camera, section.settings[cls.name], section.limits
        if camera.fault_at_photo or section.handeye is None:
            return None
        offset = math.hypot(case.dx, case.dy)
        if offset > 0.95 * limits.max_shift_mm or abs(case.alpha) > 0.95 * limits.max_rotation_deg:
            return None
        q = abs(1 - cmath.exp(1j * math.radians(camera.rotation_error_deg)) / (1 + camera.scale_error))
        if q > 0.5 or q ** (refine.max_iterations - 3) * offset >= refine.tolerance_mm / 2:
            return None
        sign = f"angle_sign {section.angle_sign:+d} and the camera's image"
        if reference.status != "ok":
            reason = reference.reason
            return f"the camera sees the mark within the limits, yet the cell's loop halts ({reason}): {sign}?"
        singular = _singular_values(section.handeye)
        mm_bound = refine.tolerance_mm * (1 + abs(camera.scale_error)) + 4 * camera.noise_px * singular[0]
        deg_bound = refine.tolerance_deg * singular[0] / singular[1] + 4 * camera.noise_deg
        _station, dx, dy, alpha, _photos = reference.logged
        mm, deg = math.hypot(dx - case.dx, dy - case.dy), abs(alpha - case.alpha)
        if mm > mm_bound or deg > deg_bound:
            return (
                f"the cell's loop stops {mm:.4f} mm and {deg:.4f} deg from the true mark (at most {mm_bound:.4f} mm "
                f"and {deg_bound:.4f} deg): {sign}?"
            )
        return None

    @classmethod
    def inputs(cls, cell, target, case: FrameCase) -> dict:
        """A station's calibration frame where the controller keeps it as a numbered base."""
        out = {}
        base_data = target.program.get("base_data")
        spec = section_of(cell).station_by_id(case.station_id).spec
        if base_data and spec.base_data is not None:
            frame = native_values(spec.frame.values, spec.frame.pose_format, "xyzabc")
            out[base_data["name"].format(n=spec.base_data)] = frame
        return out

    @classmethod
    def camera(cls, cell, case: FrameCase):
        return camera_for(cell, case)

    @classmethod
    def describe_reading(cls, case: FrameCase) -> str:
        return f"station {case.station_id} mark moved ({case.dx!r}, {case.dy!r}, {case.alpha!r}) camera {case.camera}"

    @classmethod
    def stats_lines(cls, summaries: list[dict]) -> list[str]:
        frames = [s for s in summaries if s[cls.name]["converged_cases"]]
        if not frames:
            return []
        lines = [
            "frame mode (source 001): photos to converge, final frame vs the true mark",
            f"{'target':<8}{'converged':>10}{'photos mean':>12}{'max':>5}  {'histogram':<26}"
            f"{'err max mm':>11}{'err max deg':>12}",
        ]
        for s in frames:
            f = s[cls.name]
            histogram = " ".join(f"{k}:{v}" for k, v in f["photos_histogram"].items())
            lines.append(
                f"{s['target']:<8}{f['converged_cases']:>10}{f['photos_mean']:>12.2f}{f['photos_max']:>5}  "
                f"{histogram:<26}{f['final_frame_error_mm']['max']:>11.4f}{f['final_frame_error_deg']['max']:>12.4f}"
            )
        return lines
