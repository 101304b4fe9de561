"""The [conveyor.pick] table: where parts are picked from the tracked belt and put down, per target how."""

from __future__ import annotations

from dataclasses import dataclass

from codegen.controllers import get_target
from codegen.kinds.conveyor.facts import facts

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


def _interval(ctx, table: dict, key: str, path: str, default=None) -> tuple[float, float]:
    values = ctx.numbers(table.get(key, default) if default is not None else ctx.require(table, key, path), 2, path)
    if not values[0] < values[1] or max(abs(v) for v in values) > MAX_MM:
        ctx.fail(path, f"expected [low, high] with low < high, within +-{MAX_MM:g} mm")
    return values


def parse_pick(ctx, table: dict, targets, pose_format: str) -> Pick:
    path = "conveyor.pick"
    ctx.no_unknown(table, KEYS, path)
    window = _interval(ctx, table, "window_mm", f"{path}.window_mm")
    x_range = _interval(ctx, table, "x_range_mm", f"{path}.x_range_mm")
    z_range = _interval(ctx, table, "z_range_mm", f"{path}.z_range_mm", [0.0, 100.0])
    orientation = ctx.numbers(table.get("tool_orientation", [0.0, 0.0, 180.0]), 3, f"{path}.tool_orientation")
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
    inputs = ctx.table(table, "encoder_inputs", f"{path}.encoder_inputs") if "encoder_inputs" in table else {}
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
    for target in [t for t, mode in tracking.items() if mode == "native"]:
        low, high = facts(get_target(target)).get("encoder_inputs", [0, 4095])
        if target not in inputs:
            ctx.fail(f"{path}.encoder_inputs", f"missing {target}: the digital inputs of the encoder's A and B signals")
        pair = inputs[target]
        if (
            not isinstance(pair, list)
            or len(pair) != 2
            or not all(isinstance(v, int) and not isinstance(v, bool) for v in pair)
        ):
            ctx.fail(f"{path}.encoder_inputs.{target}", "expected [A, B]: two digital input numbers")
        if pair[0] == pair[1] or not all(low <= v <= high for v in pair):
            ctx.fail(f"{path}.encoder_inputs.{target}", f"expected two different inputs in {low}..{high}")
    return Pick(
        window,
        x_range,
        z_range,
        orientation,
        approach_dz,
        place,
        dict(tracking),
        {t: tuple(inputs[t]) for t in tracking if t in inputs},
        intercept,
        capture,
        grip_s,
        speed,
    )
