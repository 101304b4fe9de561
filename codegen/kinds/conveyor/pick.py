"""The [conveyor.pick] table: where parts are picked from the tracked belt and put down, per target how."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from codegen.controllers import get_target
from codegen.kinds.conveyor.facts import facts
from codegen.sim.bus import GROUP_BITS, OFFSET, SCALE

KEYS = frozenset(
    {
        "window_mm",
        "x_range_mm",
        "z_range_mm",
        "tool_orientation",
        "approach_dz",
        "place",
        "tracking",
        "encoder_inputs",
        "intercept_mm",
        "capture_mm",
        "grip_s",
        "belt_speed_max_mm_s",
    }
)
# "native": the controller's own conveyor tracking (UR track_conveyor_linear); "intercept": the arm waits
# above a point of the belt and comes down as the part arrives there (targets/<t>.toml conveyor_tracking)
TRACKING = ("native", "intercept")
MAX_MM = 10_000.0
# An intercept (the programs' loop): the encoder read every POLL_S while the part comes, the belt's speed
# measured again over every SPEED_POLLS reads (the templates' `8`), the arm sent down lead_s before the part
# is due at the intercept point
POLL_S = 0.012
SPEED_POLLS = 8
# verify's belt of varying speed (codegen/kinds/conveyor/verify.py runs its intercepts on it): the speed
# swinging sinusoidally by VARYING_SWING of its mean (VARYING_SPEED_MM_S, or less where the cell's fastest
# belt is slower) with a period of VARYING_PERIOD_S
VARYING_SPEED_MM_S = 60.0
VARYING_SWING = 0.4
VARYING_PERIOD_S = 5.0
# x and z on a 16-bit group of inputs (codegen/sim/bus.py): 0.1 mm steps around OFFSET
GROUP_MM = ((0 - OFFSET) / SCALE, (2**GROUP_BITS - 1 - OFFSET) / SCALE)


@dataclass(frozen=True)
class Pick:
    """window_mm: the tracking window along the belt (belt y, mm: a part is picked between start and
    end, one past the end is skipped); x_range_mm, z_range_mm: where a part may lie across the belt and
    its top above the belt (the camera's readings outside them are refused); tool_orientation: a, b, c of
    the gripper at a part in the belt frame (deg, Z-Y-X); approach_dz: the gripper comes down onto the part
    and onto the place from this far above (mm); place: where the parts go (TaughtPose, base frame);
    tracking: per target, how it follows the belt; encoder_inputs: per target, the encoder's A and B
    inputs."""

    window_mm: tuple[float, float]
    x_range_mm: tuple[float, float]
    z_range_mm: tuple[float, float]
    tool_orientation: tuple[float, float, float]
    approach_dz: float
    place: object
    tracking: dict
    encoder_inputs: dict
    intercept_mm: float = 0.0  # intercept: where along the belt the gripper meets the part
    capture_mm: float = 3.0  # intercept: how far off the gripper may meet the part and still hold it
    grip_s: float = 0.0  # intercept: from the gripper's output to its hold on the part (the part travels on)
    belt_speed_max_mm_s: float = 200.0  # the fastest the belt runs: how far a tracking arm may follow past the end


def _interval(ctx, table: dict, key: str, path: str, default=None, least: float = 0.0) -> tuple[float, float]:
    values = ctx.numbers(table.get(key, default) if default is not None else ctx.require(table, key, path), 2, path)
    if not values[0] < values[1] or max(abs(v) for v in values) > MAX_MM:
        ctx.fail(path, f"expected [low, high] with low < high, within +-{MAX_MM:g} mm")
    if values[1] - values[0] < least:
        ctx.fail(
            path,
            f"{values[1] - values[0]:g} mm wide; at least {least:g} mm: the part queue carries a part's x and z "
            f"in {1 / SCALE:g} mm steps (a 16-bit group), a narrower range holds no reading",
        )
    return values


def _reading_range(ctx, values: tuple[float, float], path: str, targets) -> None:
    """A range of x or z the camera's readings must fall in: within what a 16-bit group carries where the
    target reads the queue so."""
    grouped = [t for t in targets if not facts(get_target(t)).get("names")]
    low, high = GROUP_MM
    if grouped and not (low <= values[0] and values[1] <= high):
        ctx.fail(
            path,
            f"{grouped[0]} reads the part queue as 16-bit groups of inputs: x and z within {low:g}..{high:g} mm",
        )


def lead_s(pick, work_speed_mm_s: float) -> float:
    """How long before the part reaches the intercept point an intercepting arm starts down: the descent
    of approach_dz at the work speed, as the controller's straight move takes it (no acceleration in the
    interpreter's clock, nor in this lead: a real arm needs its measured descent time here), and the
    gripper's time to hold the part once its output is set (grip_s)."""
    return pick.approach_dz / work_speed_mm_s + pick.grip_s


def lead_error_mm(lead: float, belt_speed_max_mm_s: float) -> float:
    """How far from the program's prediction verify's varying belt carries a part over the lead, at worst:
    the program predicts the part's travel from the speed it measured over its last SPEED_POLLS reads (that
    measurement up to SPEED_POLLS reads old), the belt's speed changes meanwhile. The worst over the swing's
    phase and the measurement's age, on a grid (0.0025 s and 1.5 ms steps)."""
    mean = min(VARYING_SPEED_MM_S, belt_speed_max_mm_s / (1.0 + VARYING_SWING))
    omega = 2.0 * math.pi / VARYING_PERIOD_S
    window = SPEED_POLLS * POLL_S

    def travel(t):
        return mean * (t + VARYING_SWING * (1.0 - np.cos(omega * t)) / omega)

    start = np.linspace(0.0, VARYING_PERIOD_S, 2001)[:, None]  # when the arm starts down
    measured = start - np.linspace(0.0, window, 9)[None, :]  # when the speed's measurement ended
    speed = (travel(measured) - travel(measured - window)) / window
    return float(np.abs(travel(start + lead) - travel(start) - speed * lead).max())


def parse_pick(ctx, table: dict, targets, pose_format: str) -> Pick:
    path = "conveyor.pick"
    ctx.no_unknown(table, KEYS, path)
    window = _interval(ctx, table, "window_mm", f"{path}.window_mm")
    x_range = _interval(ctx, table, "x_range_mm", f"{path}.x_range_mm", least=1 / SCALE)
    z_range = _interval(ctx, table, "z_range_mm", f"{path}.z_range_mm", [0.0, 100.0], least=1 / SCALE)
    where = f"{path}.tool_orientation"
    orientation = ctx.angles(ctx.numbers(table.get("tool_orientation", [0.0, 0.0, 180.0]), 3, where), where)
    approach_dz = ctx.number(table, "approach_dz", f"{path}.approach_dz") if "approach_dz" in table else 60.0
    if not 0 < approach_dz <= 1000:
        ctx.fail(f"{path}.approach_dz", "must be in (0, 1000] mm: the gripper comes down from above")
    place = ctx.pose("place", ctx.require(table, "place", f"{path}.place"), f"{path}.place", pose_format)
    tracking = ctx.table(table, "tracking", f"{path}.tracking")

    for target, mode in tracking.items():
        if target not in targets:
            ctx.fail(f"{path}.tracking.{target}", f"not one of the cell's targets ({', '.join(targets)})")
        if mode not in TRACKING:
            ctx.fail(f"{path}.tracking.{target}", f"expected one of {', '.join(TRACKING)}")
        modes = facts(get_target(target)).get("tracking", [])
        if mode not in modes:
            have = ", ".join(modes) if modes else "none: codegen has no conveyor program for it"
            ctx.fail(f"{path}.tracking.{target}", f"{mode!r}: what codegen builds for {target}: {have}")
    if not tracking:
        ctx.fail(f"{path}.tracking", 'expected at least one target, e.g. { ur = "native" }')
    for key, values in (("x_range_mm", x_range), ("z_range_mm", z_range)):
        _reading_range(ctx, values, f"{path}.{key}", tracking)
    inputs = _encoder_inputs(ctx, table, tracking, f"{path}.encoder_inputs")
    intercept = window[0] + 0.25 * (window[1] - window[0])
    if "intercept_mm" in table:
        intercept = ctx.number(table, "intercept_mm", f"{path}.intercept_mm")
        if not window[0] <= intercept <= window[1]:
            ctx.fail(f"{path}.intercept_mm", "must lie in the window")
    grip_s = ctx.number(table, "grip_s", f"{path}.grip_s") if "grip_s" in table else 0.0
    if not 0 <= grip_s <= 2:
        ctx.fail(f"{path}.grip_s", "must be in [0, 2] s: the gripper's time from its output to holding the part")
    speed = (
        ctx.number(table, "belt_speed_max_mm_s", f"{path}.belt_speed_max_mm_s")
        if "belt_speed_max_mm_s" in table
        else 200.0
    )
    if not 0 < speed <= 5000:
        ctx.fail(f"{path}.belt_speed_max_mm_s", "must be in (0, 5000] mm/s")
    capture = ctx.number(table, "capture_mm", f"{path}.capture_mm") if "capture_mm" in table else 3.0
    if not 0 < capture <= 50:
        ctx.fail(f"{path}.capture_mm", "must be in (0, 50] mm")
    return Pick(
        window,
        x_range,
        z_range,
        orientation,
        approach_dz,
        place,
        dict(tracking),
        inputs,
        intercept,
        capture,
        grip_s,
        speed,
    )


def _encoder_inputs(ctx, table: dict, tracking: dict, path: str) -> dict:
    """[conveyor.pick] encoder_inputs = { <target> = [A, B] }: the digital inputs of the encoder's A and B
    signals, for each target that tracks the belt natively (and for no other: an intercepting program reads
    the PLC's count)."""
    raw = ctx.table(table, "encoder_inputs", path) if "encoder_inputs" in table else {}
    native = [t for t, mode in tracking.items() if mode == "native"]
    for key in raw:
        if key not in native:
            why = (
                f"{key} intercepts the parts (it reads the PLC's count)" if key in tracking else "not a tracking target"
            )
            allowed = ", ".join(native) if native else "none"
            ctx.fail(f"{path}.{key}", f"{why}: only a target tracking natively reads the encoder; allowed: {allowed}")
    out = {}
    for target in native:
        low, high = facts(get_target(target)).get("encoder_inputs", [0, 4095])
        if target not in raw:
            ctx.fail(path, f"missing {target}: the digital inputs of the encoder's A and B signals")
        pair = raw[target]
        if (
            not isinstance(pair, list)
            or len(pair) != 2
            or not all(isinstance(v, int) and not isinstance(v, bool) for v in pair)
        ):
            ctx.fail(f"{path}.{target}", "expected [A, B]: two digital input numbers")
        if pair[0] == pair[1] or not all(low <= v <= high for v in pair):
            ctx.fail(f"{path}.{target}", f"expected two different inputs in {low}..{high}")
        out[target] = tuple(pair)
    return out


def check_lead(ctx, pick, work_speed_mm_s: float) -> None:
    """An intercept predicts where the part will be when the gripper holds it: over the lead (the descent and
    the grip) a belt whose speed changes carries the part off that prediction, which must stay within the
    gripper's capture (verify's varying belt is the measure)."""
    if "intercept" not in pick.tracking.values():
        return
    lead = lead_s(pick, work_speed_mm_s)
    error = lead_error_mm(lead, pick.belt_speed_max_mm_s)
    if error > pick.capture_mm:
        ctx.fail(
            "conveyor.pick.grip_s",
            f"an intercepting arm starts down {lead:.3g} s before the part is due (approach_dz at the work speed, "
            f"then grip_s): a belt whose speed swings +-{VARYING_SWING:.0%} over {VARYING_PERIOD_S:g} s (verify's "
            f"varying belt) carries the part up to {error:.2f} mm off the program's prediction in that time, beyond "
            f"capture_mm ({pick.capture_mm:g} mm): a quicker gripper, a shorter approach_dz or a faster work speed",
        )
