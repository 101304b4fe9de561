"""The envelope check: every taught pose, corrected by every reading the guard lets through, is reachable
in its taught configuration, inside the joint limits and away from the wrist singularity by a margin."""

from __future__ import annotations

import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass

import numpy as np

from codegen.controllers import get_target
from codegen.decimals import format_literal
from codegen.kinds.station.region import offsets, remember_plan, station_region
from codegen.kinds.station.section import section_of, stations_of
from codegen.robot.margins import least_joint_margin, singular_distance, wrist_angle
from codegen.robot.taught import ReachError, configuration


@dataclass(frozen=True)
class StationMargin:
    station_id: int
    station: str
    joint_margin_deg: float  # the least distance of any axis from its limits over the region
    joint_axis: int  # 1-based, the axis of that least distance
    wrist_margin_deg: float  # the least distance of the wrist axis from its singular angle (0, +-180)
    step_deg: float  # the largest joint change between neighbouring readings (the sampling's resolution)
    pose: str  # the pose with the least joint margin
    posture: str = ""  # the posture chosen to clear the cell where it is not the one nearest the home (else "")
    wrist_pose: str = ""  # the pose nearest the wrist singularity

    @property
    def id_text(self) -> str:
        return f"{self.station_id} {self.station}"


@dataclass(frozen=True)
class TargetEnvelope:
    target: str
    model: str
    samples: int  # readings per station
    stations: tuple[StationMargin, ...]

    def text(self) -> str:
        """One line per station: the margins over the correction region."""
        lines = [f"envelope {self.target} ({self.model}): {self.samples} readings per station, every pose reachable"]
        for m in self.stations:
            lines.append(
                f"  station {m.id_text}: {m.joint_margin_deg:.1f} deg to the nearest joint limit (axis "
                f"{m.joint_axis}, pose {m.pose}), wrist {m.wrist_margin_deg:.1f} deg from its singularity (pose "
                f"{m.wrist_pose})"
            )
            if m.posture:
                lines.append(f"    {m.posture}")
        return "\n".join(lines)

    def as_json(self) -> dict:
        return {
            "target": self.target,
            "arm": self.model,
            "readings_per_station": self.samples,
            "stations": [
                {
                    "id": m.station_id,
                    "name": m.station,
                    "joint_margin_deg": round(m.joint_margin_deg, 3),
                    "joint_axis": m.joint_axis,
                    "wrist_margin_deg": round(m.wrist_margin_deg, 3),
                    "step_deg": round(m.step_deg, 3),
                    "pose": m.pose,
                    "wrist_pose": m.wrist_pose,
                    "posture": m.posture,
                }
                for m in self.stations
            ],
        }


def check_target(cell, target: str) -> TargetEnvelope:
    """Raise ReachError naming the station, pose, worst reading and limit; else every station's margins."""
    arm = cell.robot.arms[target]
    margins = [_station(cell, target, arm, station) for station in stations_of(cell)]
    samples = len(station_region(cell, target, stations_of(cell)[0]).offsets)
    return TargetEnvelope(target, arm.model, samples, tuple(margins))


def station_margin(cell, target: str, station) -> StationMargin:
    """One station's margins over its correction region on the target's arm, or ReachError naming the pose."""
    return _station(cell, target, cell.robot.arms[target], station)


def _station(cell, target: str, arm, station) -> StationMargin:
    form = get_target(target).configuration
    wanted = cell.robot.margins
    region = station_region(cell, target, station)
    joints = region.joints
    for m, pose in enumerate(region.taught):
        q = joints[:, m]
        where = f"station {station.id} {station.name!r} pose {pose.name!r} ({target}, {arm.model})"
        missing = np.isnan(q).any(axis=-1)
        if missing.any():
            i = int(np.argmax(missing))
            reading = _reading(region.offsets[i])
            raise ReachError(f"{where}: out of reach or beyond a joint limit for the reading {reading}")
        changed = region.branch[:, m] != pose.branch
        if changed.any():
            i = int(np.argmax(changed))
            raise ReachError(
                f"{where}: the arm would change configuration (taught {_shown(configuration(form, arm, pose.joints))}, "
                f"here {_shown(configuration(form, arm, q[i]))}) for the reading {_reading(region.offsets[i])}"
            )
        least, worst = least_joint_margin(arm, q)  # q: (N, 6)
        if least < wanted.joint_deg:
            raise ReachError(
                f"{where}: axis {worst[1] + 1} comes within {least:.2f} deg of its limit "
                f"(margin asked: {wanted.joint_deg:g} deg) for the reading {_reading(region.offsets[worst[0]])}"
            )
        wrist = singular_distance(wrist_angle(arm, q))
        if wrist.min() < wanted.wrist_deg:
            i = int(np.argmin(wrist))
            raise ReachError(
                f"{where}: the wrist comes within {wrist[i]:.2f} deg of its singularity (axis 5 at "
                f"{q[i, 4]:.2f} deg; margin asked: {wanted.wrist_deg:g} deg) for the reading "
                f"{_reading(region.offsets[i])}"
            )
    least, (_n, m, axis) = least_joint_margin(arm, joints)
    wrist = singular_distance(wrist_angle(arm, joints))  # (N, poses)
    wrist_at = np.unravel_index(np.argmin(wrist), wrist.shape)
    step = _step(joints[1:], *region.grid)
    if step > wanted.joint_deg:
        raise ReachError(
            f"station {station.id} {station.name!r} ({target}, {arm.model}): an axis moves {step:.2f} deg between "
            f"neighbouring checked readings, more than the joint margin asked ({wanted.joint_deg:g} deg): "
            "the check cannot vouch for the readings between them"
        )
    return StationMargin(
        station_id=station.id,
        station=station.name,
        joint_margin_deg=least,
        joint_axis=int(axis) + 1,
        wrist_margin_deg=float(wrist[wrist_at]),
        step_deg=step,
        pose=region.taught[m].name,
        wrist_pose=region.taught[wrist_at[1]].name,
    )


def _step(grid_joints: np.ndarray, rotations: int, directions: int) -> float:
    """The largest joint change between a reading and its neighbour in the sampling (next direction on
    its ring, or next rotation): how far the check is from the readings between samples. A turn the
    controller takes the other way round (the shortest turn from where the arm stands) is not a step."""
    grid = grid_joints.reshape(rotations, -1, *grid_joints.shape[1:])
    ring = grid[:, 1:].reshape(rotations, -1, directions, *grid_joints.shape[1:])
    steps = [_wrapped(np.diff(grid, axis=0)), _wrapped(ring - np.roll(ring, 1, axis=2))]
    return float(max(steps))


def _wrapped(delta: np.ndarray) -> float:
    return float(np.abs((delta + 180.0) % 360.0 - 180.0).max())


def _shown(value) -> str:
    """A configuration as the program's form has it, for reading: joints to 0.1 deg, bits and quadrants as they are."""
    if isinstance(value, tuple | list) and any(isinstance(v, float) for v in value):
        return "[" + ", ".join(format_literal(float(v), 1) for v in value) + "]"
    return str(value)


def _reading(offset) -> str:
    dx, dy, rot = offset
    return f"(shift {dx:+.2f}, {dy:+.2f} mm, rotation {rot:+.2f} deg)"


PARALLEL_STATIONS = 50  # from this many stations the targets are checked in parallel processes
_FORKED: dict = {}  # the cell a forked worker checks (inherited, not pickled)


def check(cell, only: list[str] | None = None) -> list[TargetEnvelope]:
    """Every target with an arm (of `only`, if given); [] when the cell names no robot. A large cell's
    targets are checked in parallel processes; what the programs need of each station comes back."""
    if cell.robot is None or not stations_of(cell):  # a cell without stations: its kinds prove their own reach
        return []
    targets = [target for target in cell.targets if target in cell.robot.arms and (only is None or target in only)]
    if not targets:
        return []
    cores = min(len(targets), os.cpu_count() or 1)
    if cores < 2 or len(stations_of(cell)) < PARALLEL_STATIONS or "fork" not in multiprocessing.get_all_start_methods():
        return [check_target(cell, target) for target in targets]
    workers = os.cpu_count() or 1
    size = -(-len(stations_of(cell)) // (2 * workers))  # chunks of stations: the work spreads evenly
    tasks = [(target, i, i + size) for target in targets for i in range(0, len(stations_of(cell)), size)]
    _FORKED["cell"] = cell
    try:
        context = multiprocessing.get_context("fork")
        with ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
            results = list(pool.map(_check_forked, tasks))
    finally:
        _FORKED.clear()
    margins: dict[str, list[StationMargin]] = {target: [] for target in targets}
    for (target, low, _high), (chunk, plans, error) in zip(tasks, results, strict=True):
        if error is not None:
            raise ReachError(error)
        margins[target].extend(chunk)
        for station, (taught, named) in zip(stations_of(cell)[low:], plans, strict=False):
            remember_plan(cell, target, station, taught, named)
    limits = section_of(cell).limits
    samples = len(offsets(limits.max_shift_mm, limits.max_rotation_deg))
    return [TargetEnvelope(t, cell.robot.arms[t].model, samples, tuple(margins[t])) for t in targets]


def _check_forked(task: tuple[str, int, int]):
    """One target's stations low..high-1 in a forked worker: their margins and plans, or the refusal."""
    target, low, high = task
    cell = _FORKED["cell"]
    arm = cell.robot.arms[target]
    try:
        chunk = [_station(cell, target, arm, station) for station in stations_of(cell)[low:high]]
    except ReachError as exc:
        return None, None, str(exc)
    regions = [station_region(cell, target, s) for s in stations_of(cell)[low:high]]
    return chunk, [(region.taught, region.named) for region in regions], None


__all__ = ["ReachError", "TargetEnvelope", "check"]
