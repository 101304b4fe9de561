"""The [conveyor.pick] table: where parts are picked from the tracked belt and put down, per target how."""

from __future__ import annotations

from dataclasses import dataclass, field

from codegen.controllers import get_target
from codegen.kinds.conveyor.keys import PICK
from codegen.kinds.conveyor.kind import KIND
from codegen.model.io import GROUP_BITS, OFFSET, SCALE
from codegen.model.loader import Loader, build

# x and z on a 16-bit group of inputs (codegen.model.io): 0.1 mm steps around OFFSET
GROUP_MM = ((0 - OFFSET) / SCALE, (2**GROUP_BITS - 1 - OFFSET) / SCALE)


@dataclass(frozen=True)
class Pick:
    """window_mm: the tracking window along the belt (belt y, mm: a part is picked between start and
    end, one past the end is skipped); x_range_mm, z_range_mm: where a part may lie across the belt and
    its top above the belt (the camera's readings outside them are refused); tool_orientation: a, b, c of
    the gripper at a part in the belt frame (deg, Z-Y-X); approach_dz: the gripper comes down onto the part
    and onto the place from this far above (mm); place: where the parts go (TaughtPose, base frame);
    tracking: per target, how it follows the belt; encoder_inputs: per target, the encoder's A and B
    inputs; trigger_input: per target, the robot's input the camera's trigger is wired to (a native UR
    program latches its own encoder there); part_mass_kg, part_cog_mm: the part (its centre of gravity in the
    tool frame), the payload while the gripper holds it; overtravel_mm: the gripper comes down this far past the part's
    top at the grip (a suction cup pressed on); place_clear: per target, the input that says the
    place is free (none: the program does not ask), waited for place_timeout_s; zone_output: per target, the output
    on while the arm is over the belt below the clear height (the PLC stops the belt when the robot stops then);
    min_gap_mm: how close a part may follow the one before and still be picked (ABB native: the unit's Sync
    Separation); unit: per target, the belt's mechanical unit (ABB native), unit_axis its logical axis; no_part_s:
    the wait for the next part says so once after this long (and goes on); belt_stop_s: the encoder still this long
    while a part is on its way: the belt stands (a message)."""

    window_mm: tuple[float, float]
    x_range_mm: tuple[float, float]
    z_range_mm: tuple[float, float]
    tool_orientation: tuple[float, float, float]
    approach_dz: float
    place: object
    tracking: dict
    encoder_inputs: dict
    intercept_mm: float = 0.0  # intercept: where along the belt the gripper meets the part
    overtravel_mm: float = 2.0  # the gripper comes down this far past the part's top (a suction cup pressed on)
    capture_mm: float = 3.0  # intercept: how far off the gripper may meet the part and still hold it
    grip_s: tuple[float, float] = (0.0, 0.0)  # from the gripper's output to its hold on the part (least, most)
    belt_speed_max_mm_s: float = 200.0  # the fastest the belt runs: how far a tracking arm may follow past the end
    belt_accel_mm_s2: float = 0.0  # the fastest the belt's speed changes (intercept: its speed estimate's error)
    count_latency_s: tuple[float, float] = (0.0, 0.0)  # intercept: the count's age when the program reads it
    motion_start_s: tuple[float, float] = (0.0, 0.0)  # intercept: from the move instruction to the arm moving
    part_mass_kg: float = 0.0
    part_cog_mm: tuple[float, float, float] = (0.0, 0.0, 0.0)
    place_clear: dict = field(default_factory=dict)
    zone_output: dict = field(default_factory=dict)  # per target: on while the arm is below the clear height
    place_timeout_s: float = 10.0
    min_gap_mm: float = 0.0
    unit: dict = field(default_factory=dict)
    unit_axis: dict = field(default_factory=dict)  # ABB native: the unit's logical axis (7..12: eax_a..eax_f)
    unit_position_check: bool = True  # ABB native: the connected object's position checked against the PLC's count
    trigger_input: dict = field(default_factory=dict)
    part_size_mm: tuple[float, float, float] | None = None  # the part as a box along the tool frame's axes (inertia)
    no_part_s: float = 30.0  # the wait for the next part: a message after this long, then on waiting
    belt_stop_s: float = 2.0  # the encoder still this long while a part is on its way: the belt stands (a message)
    timer: dict = field(default_factory=dict)  # intercept: the controller's numbered timer the program measures with

    @property
    def clear_mm(self) -> float:
        """The clear height (mm above the belt): the empty gripper's tip waits and leaves a part approach_dz above the
        tallest part z_range_mm allows (a part before the one awaited may pass under it)."""
        return self.z_range_mm[1] + self.approach_dz

    @property
    def lift_dz(self) -> float:
        """The lift with a part held (mm above the held part's top): the part's bottom at the clear height, so the tip
        at z_range_mm's top + the part's own height (its z) + approach_dz; the travel to the place starts there."""
        return self.clear_mm

    def mean(self, key: str) -> float:
        """The middle of a (least, most) interval of the cell (grip_s, count_latency_s, motion_start_s)."""
        low, high = getattr(self, key)
        return 0.5 * (low + high)


def _interval(ctx, values: tuple[float, float], path: str, least: float = 0.0) -> tuple[float, float]:
    """A [low, high] range of the belt: low below high, at least `least` wide."""
    if not values[0] < values[1]:
        ctx.fail(path, f"expected [low, high] with low < high, got {list(values)}")
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
    grouped = [t for t in targets if not KIND.facts(get_target(t)).get("names")]
    low, high = GROUP_MM
    if grouped and not (low <= values[0] and values[1] <= high):
        ctx.fail(
            path,
            f"{grouped[0]} reads the part queue as 16-bit groups of inputs: x and z within {low:g}..{high:g} mm",
        )


def _seconds(ctx, value, path: str) -> tuple[float, float]:
    """A duration the cell states as a number or as [least, most] (s), as (least, most)."""
    low, high = (value, value) if isinstance(value, float) else value
    if not low <= high:
        ctx.fail(path, f"must be a duration, or [least, most] with least <= most, got {list(value)}")
    return float(low), float(high)


def parse_pick(ctx, loader: Loader, table, targets) -> Pick:
    """[conveyor.pick]: its keys as declared (keys.py), then the rules between them and the cell's targets."""
    path = "conveyor.pick"
    # per tracking target, below (a target that reads no encoder told so before its value is read)
    keep = {key: (lambda raw, where: raw) for key in ("place_clear", "zone_output", "encoder_inputs")}
    values = loader.table(PICK, table, path, readers=keep)
    window = _interval(ctx, values["window_mm"], f"{path}.window_mm")
    _interval(ctx, values["x_range_mm"], f"{path}.x_range_mm", least=1 / SCALE)
    _interval(ctx, values["z_range_mm"], f"{path}.z_range_mm", least=1 / SCALE)
    tracking = _tracking(ctx, values["tracking"], targets, f"{path}.tracking")
    for key in ("x_range_mm", "z_range_mm"):
        _reading_range(ctx, values[key], f"{path}.{key}", tracking)
    values["encoder_inputs"] = _encoder_inputs(
        ctx, loader, values["encoder_inputs"], tracking, f"{path}.encoder_inputs"
    )
    if values["intercept_mm"] is None:
        values["intercept_mm"] = window[0] + 0.25 * (window[1] - window[0])
    elif not window[0] <= values["intercept_mm"] <= window[1]:
        ctx.fail(f"{path}.intercept_mm", "must lie in the window")
    for key in ("grip_s", "count_latency_s", "motion_start_s"):
        values[key] = _seconds(ctx, values[key], f"{path}.{key}")
    if values["overtravel_mm"] >= values["approach_dz"]:
        ctx.fail(f"{path}.overtravel_mm", f"must be less than approach_dz ({values['approach_dz']:g} mm)")
    if values["min_gap_mm"] > window[1] - window[0]:
        ctx.fail(f"{path}.min_gap_mm", f"must be in [0, {window[1] - window[0]:g}] mm (the window's width)")
    tracked = Loader(ctx, loader.pose_format, tuple(tracking))  # a signal per tracking target
    for key in ("place_clear", "zone_output"):
        values[key] = tracked.value(PICK[key], values[key], f"{path}.{key}") if values[key] is not None else {}
    natives = [t for t, mode in tracking.items() if mode == "native"]
    values["unit"] = _named(
        ctx, values["unit"] or {}, "unit", [t for t in natives if KIND.facts(get_target(t)).get("unit")], path
    )
    values["unit_axis"] = _axis(ctx, values["unit_axis"] or {}, list(values["unit"]), path)
    triggered = [t for t in natives if KIND.facts(get_target(t)).get("trigger")]
    values["trigger_input"] = _numbered_input(ctx, values["trigger_input"] or {}, "trigger_input", triggered, path)
    intercepts = [t for t, mode in tracking.items() if mode == "intercept"]
    values["timer"] = _timer(ctx, values["timer"] or {}, intercepts, path)
    return build(Pick, values, tracking=tracking)


def _timer(ctx, given: dict, intercepts: list[str], path: str) -> dict:
    """Per intercepting target whose program measures the belt's speed over one of the controller's numbered timers
    (targets/<t>.toml [program.conveyor] timers: how many there are), the one the cell gives it."""
    needed = [t for t in intercepts if KIND.facts(get_target(t)).get("timers")]
    ctx.no_unknown(given, set(needed), f"{path}.timer")
    for target in needed:
        if target not in given:
            count = KIND.facts(get_target(target))["timers"]
            ctx.fail(f"{path}.timer", f"missing {target}: the controller's timer (1..{count}) the program may use")
    return {t: given[t] for t in needed}


def _tracking(ctx, tracking: dict, targets, path: str) -> dict:
    for target, mode in tracking.items():
        if target not in targets:
            ctx.fail(f"{path}.{target}", f"not one of the cell's targets ({', '.join(targets)})")
        modes = KIND.facts(get_target(target)).get("tracking", [])
        if mode not in modes:
            have = ", ".join(modes) if modes else "none: codegen has no conveyor program for it"
            ctx.fail(f"{path}.{target}", f"{mode!r}: what codegen builds for {target}: {have}")
    return dict(tracking)


def _encoder_inputs(ctx, loader: Loader, raw, tracking: dict, path: str) -> dict:
    """[conveyor.pick] encoder_inputs = { <target> = [A, B] }: the digital inputs of the encoder's A and B
    signals, for each target whose native tracking reads the encoder on the robot's inputs (its facts'
    encoder_inputs), and for no other (an intercepting program reads the PLC's count, ABB's unit its own)."""
    reading = [
        t for t, mode in tracking.items() if mode == "native" and KIND.facts(get_target(t)).get("encoder_inputs")
    ]
    for key in raw if isinstance(raw, dict) else ():
        if key not in reading:
            why = f"{key} does not read the encoder on its own inputs" if key in tracking else "not a tracking target"
            allowed = ", ".join(reading) if reading else "none"
            ctx.fail(
                f"{path}.{key}", f"{why}: only a target tracking natively on the robot's inputs; allowed: {allowed}"
            )
    given = {} if raw is None else loader.value(PICK["encoder_inputs"], raw, path)
    for target in reading:
        if target not in given:
            ctx.fail(path, f"missing {target}: the digital inputs of the encoder's A and B signals")
        if given[target][0] == given[target][1]:
            ctx.fail(f"{path}.{target}", f"expected two different inputs, got {list(given[target])}")
    return {t: given[t] for t in reading}


def _named(ctx, given: dict, key: str, needed: list[str], path: str) -> dict:
    """A name per target that needs one (the belt's mechanical unit), default the target's facts' (`unit`)."""
    ctx.no_unknown(given, set(needed), f"{path}.{key}")
    return {t: given.get(t, KIND.facts(get_target(t))[key]) for t in needed}


def _axis(ctx, given: dict, needed: list[str], path: str) -> dict:
    """The logical axis per target with a mechanical unit: the cell's, default the target's facts' `unit_axis`."""
    ctx.no_unknown(given, set(needed), f"{path}.unit_axis")
    return {t: given.get(t, KIND.facts(get_target(t))["unit_axis"]) for t in needed}


def _numbered_input(ctx, given: dict, key: str, needed: list[str], path: str) -> dict:
    """A digital input number per target that needs one (the camera's trigger wired to the robot)."""
    ctx.no_unknown(given, set(needed), f"{path}.{key}")
    for target in needed:
        if target not in given:
            ctx.fail(f"{path}.{key}", f"missing {target}: the digital input the camera's trigger is wired to")
    return {t: given[t] for t in needed}


def check_inputs(ctx, pick: Pick, feedback: dict, output: dict | None = None) -> None:
    """Per target, the inputs the pick program reads are distinct: the gripper's sensor ([cell.io] feedback), the
    encoder's A and B, the camera's trigger and the place's input; its two outputs too (the gripper's, the belt
    zone's)."""
    for target, zone in pick.zone_output.items():
        if output is not None and output.get(target) == zone:
            ctx.fail(f"conveyor.pick.zone_output.{target}", f"output {zone} is cell.io.output.{target} too")
    for target in pick.tracking:
        named = [(f"cell.io.feedback.{target}", feedback.get(target))]
        named += [(f"conveyor.pick.encoder_inputs.{target}", v) for v in pick.encoder_inputs.get(target, ())]
        named += [
            (f"conveyor.pick.{key}.{target}", getattr(pick, key).get(target))
            for key in ("trigger_input", "place_clear")
        ]
        seen: dict = {}
        for key, value in named:
            if value is not None and value in seen:
                ctx.fail(key, f"input {value} is {seen[value]} too: each input of the program says one thing")
            seen.setdefault(value, key)
