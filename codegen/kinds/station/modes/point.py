"""The point mode (source 000): one camera reading moves every taught pose of the station rigidly."""

from __future__ import annotations

import math
import random
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from codegen import derived
from codegen.emit import owned
from codegen.guard import (
    GUARD_CODES,
    INVALID_READING,
    READING_RANGE_DEG,
    ROTATION_OVER_LIMIT,
    SHIFT_OVER_LIMIT,
)
from codegen.kinds.station.mode import StationMode
from codegen.kinds.station.point.keys import KEYS
from codegen.kinds.station.point.reference import NAME, PointSpec, Reading, expected_trace
from codegen.kinds.station.section import section_of, station_label
from codegen.model.validate import metres_text, read_as_metres
from codegen.model.vision import READ, SECOND_LOOK_MM
from codegen.poses import planar_motions, wrap_deg
from codegen.reference import ExpectedTrace

if TYPE_CHECKING:
    from codegen.kinds.station.cases import Case

MARK_DECIMALS = 6


def _ulp32(value: float) -> float:
    return float(np.spacing(np.float32(abs(value))))


def _fixed(ctx, names: tuple[str, ...], poses: list[str], path: str) -> frozenset[str]:
    """The station's `fixed` poses: each a pose of the station, the work pose (the last) not among them."""
    for i, name in enumerate(names):
        if name not in poses:
            ctx.fail(f"{path}.fixed[{i}]", f"not a pose of the station; its poses: {', '.join(poses)}")
        if name == poses[-1]:
            ctx.fail(f"{path}.fixed[{i}]", f"{name!r} is the work pose, which the reading moves (the deviation line)")
    return frozenset(names)


class PointMode(StationMode):
    name = NAME
    order = 0
    cell_file = KEYS
    model_inputs = frozenset({"angle_sign", "calibration", "derivation"})
    log_prefixes = ("deviation",)
    log_names = ("station", "dx1", "dy1", "dx2", "dy2", "dtheta")
    answer_names = {READ: ("x", "y", "theta")}

    @classmethod
    def station_scene(cls, cell, station) -> list[dict]:
        from codegen.kinds.station.point.scene import objects  # the page's: a cell loads without it

        return objects(cell, station)

    @classmethod
    def commands(cls) -> list:
        from codegen.kinds.station.point.commands import correct  # click: the command line's alone

        return [(None, correct)]

    @classmethod
    def parse(cls, ctx, values: dict, path: str) -> PointSpec:
        mark = values["mark"]
        reach = read_as_metres(mark[:2])
        if reach is not None:
            ctx.fail(f"{path}.mark", f"x, y lie {reach:g} mm from the robot's base: {metres_text(reach, 'A mark is')}")
        for name, pose in values["poses"].items():  # base frame; a "ur" cell's poses are metres as they should be
            reach = None if pose.pose_format == "ur" else read_as_metres(pose.values[:3])
            if reach is not None:
                ctx.fail(
                    f"{path}.poses.{name}",
                    f"x, y, z lie within {reach:g} mm of the robot's base: {metres_text(reach, 'A taught pose is')}",
                )
        if abs(mark[2]) > READING_RANGE_DEG:
            ctx.fail(f"{path}.mark[2]", f"theta must be within +-{READING_RANGE_DEG:g} deg")
        return PointSpec(mark, _fixed(ctx, values["fixed"] or (), list(values["poses"]), path))

    @classmethod
    def moved(cls, spec: PointSpec, mm: float) -> PointSpec:
        x, y, theta = spec.mark
        return replace(spec, mark=(x + mm, y, theta))

    @classmethod
    def region(cls, cell, station, offsets) -> np.ndarray:
        # D = Trans(tn) Rz(phi) Trans(-t) with tn = t + (dx, dy): D = Trans(t) . (Trans(d) Rz(phi)) . Trans(-t)
        x, y, _theta = station.spec.mark
        corr = planar_motions(offsets)
        corr[:, :2, 3] += np.array([x, y]) - np.einsum("nij,j->ni", corr[:, :2, :2], [x, y])
        poses = np.array([p.matrix() for p in station.path])
        out = np.einsum("nij,mjk->nmik", corr, poses)
        fixed = [i for i, p in enumerate(station.path) if p.name in station.spec.fixed]
        out[:, fixed] = poses[fixed]  # on the robot's own carrier: the reading does not move them
        return out

    @classmethod
    def cell_context(cls, cell, target, emitter) -> dict:
        # the derivation's blocks: D = Trans(tn) Rz(phi) Trans(-t) ("frame") and Pn = D . P ("point")
        return {
            "correction": owned(derived.printed(target.dialect, "frame")),
            "point": owned(derived.printed(target.dialect, "point")),
        }

    @classmethod
    def station_context(cls, cell, station, target, emitter) -> dict:
        origin = station_label(cell, station)
        return {
            "fixed": [p.name in station.spec.fixed for p in station.path],
            "mark_ident": emitter.identifier(f"m{station.id}_", station.name, f"{origin} mark"),
            "mark": [emitter.number(v, MARK_DECIMALS) for v in station.spec.mark],
            "messages": {
                reason: emitter.string(cls.fitted_message(cell, reason, station, target.string_max))
                for reason in GUARD_CODES
            },
        }

    @classmethod
    def cases(cls, cell, station, count: int, rng: random.Random) -> list[Case]:
        from codegen.kinds.station.cases import Case  # verify's: a cell loads without the simulator

        limits = section_of(cell).limits
        shift, rot = limits.max_shift_mm, limits.max_rotation_deg
        tx, ty, t_theta = station.spec.mark

        def reading(dx, dy, dtheta):
            return Reading(station.id, tx + dx, ty + dy, wrap_deg(t_theta + dtheta))

        cases = []
        for _ in range(count):
            r = shift * math.sqrt(rng.random())
            a = rng.uniform(-math.pi, math.pi)
            cases.append(Case("random", reading(r * math.cos(a), r * math.sin(a), rng.uniform(-rot, rot))))
        cases.append(cls.nominal_case(cell, station))
        for sx, sy in ((1, 0), (-1, 0), (0, 1), (0, -1), (0.6, 0.8)):
            cases.append(Case("at_shift_limit", reading(sx * shift, sy * shift, 0.0)))
            cases.append(Case("inside_shift_limit", reading(sx * (shift - 1e-3), sy * (shift - 1e-3), 0.0)))
            cases.append(Case("beyond_shift_limit", reading(sx * (shift + 1e-3), sy * (shift + 1e-3), 0.0)))
        for sign in (1, -1):
            cases.append(Case("phi_at_limit", reading(0.0, 0.0, sign * rot)))
            cases.append(Case("phi_at_limit_with_shift", reading(0.3 * shift, -0.4 * shift, sign * rot)))
            cases.append(Case("inside_rotation_limit", reading(0.0, 0.0, sign * (rot - 1e-3))))
            cases.append(Case("beyond_rotation_limit", reading(0.0, 0.0, sign * (rot + 1e-3))))
        for k in range(8):  # the region's corners: shift and rotation both near their limits
            a = k * math.pi / 4
            for sign in (1, -1):
                dx, dy = 0.999 * shift * math.cos(a), 0.999 * shift * math.sin(a)
                cases.append(Case("corner", reading(dx, dy, sign * 0.999 * rot)))
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
        return cases

    @classmethod
    def nominal_case(cls, cell, station) -> Case:
        from codegen.kinds.station.cases import Case  # verify's: a cell loads without the simulator

        return Case("zero_shift", Reading(station.id, *station.spec.mark))

    @classmethod
    def edge_spec(cls) -> PointSpec:
        """A mark near 180 deg, so readings around it wrap."""
        return PointSpec((300.0, 200.0, 179.5))

    @classmethod
    def accepted(cls, cell, reading: Reading) -> tuple[list[ExpectedTrace], bool]:
        """The reference trace, plus the other side of a limit when the reading is within float32
        resolution of it (a float32 controller may decide either way there)."""
        reference = expected_trace(cell, reading)
        station = section_of(cell).station_by_id(reading.station_id)
        if reference.reason == INVALID_READING or station is None:
            return [reference], False
        tx, ty, t_theta = station.spec.mark
        limits = section_of(cell).limits
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
                    out.append(replace(free, status="halt", reason=SHIFT_OVER_LIMIT, moves=(), logged=None))
                elif rot_over:
                    out.append(replace(free, status="halt", reason=ROTATION_OVER_LIMIT, moves=(), logged=None))
                else:
                    out.append(free)
        return out, True

    @classmethod
    def answer(cls, cell, target, reading: Reading) -> dict:
        names = target.program["inputs"]
        return {
            names["station"]: reading.station_id,
            names["x"]: reading.x,
            names["y"]: reading.y,
            names["theta"]: reading.theta,
        }

    @classmethod
    def second_look(cls, reading: Reading) -> Reading:
        return replace(reading, x=reading.x + SECOND_LOOK_MM, y=reading.y + SECOND_LOOK_MM)

    @classmethod
    def previous(cls, cell, target, station) -> dict:
        """The station read at its calibration mark: the reading a stale vision PC would replay."""
        return cls.answer(cell, target, Reading(station.id, *station.spec.mark))

    @classmethod
    def describe_reading(cls, reading: Reading) -> str:
        return f"station {reading.station_id} reading ({reading.x!r}, {reading.y!r}, {reading.theta!r})"
