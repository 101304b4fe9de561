"""The envelope check: every taught pose, corrected by every reading the guard lets through, is reachable
in its taught configuration, inside the joint limits and away from the wrist singularity by a margin."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from codegen.controllers import get_target
from codegen.decimals import format_literal
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


def station_margin(cell, target: str, station, region) -> StationMargin:
    """One station's margins over its correction region (codegen/kinds/station/region.py StationRegion) on the target's
    arm, or ReachError naming the pose and the reading."""
    arm = cell.robot.arms[target]
    form = get_target(target).configuration
    wanted = cell.robot.margins
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


__all__ = ["ReachError", "StationMargin", "TargetEnvelope", "station_margin"]
