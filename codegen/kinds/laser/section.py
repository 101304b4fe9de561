"""The [laser] table of a cell file: source 003's two-beam sensor station, the pin and the calibration's moves."""

from __future__ import annotations

import math
from dataclasses import dataclass

from codegen.controllers import get_target
from codegen.dialects import get_dialect
from codegen.kinds.laser.keys import LASER
from codegen.kinds.laser.kind import KIND
from codegen.model.cell import TaughtPose
from codegen.model.loader import Loader, build

DEPTH_STEP_MIN_MM = 2.0
OWN_PREFIX = "lsr_"  # the program's own names: a production tool's name must not start so


@dataclass(frozen=True)
class Laser:
    """sensor_frame: S in the base frame (its xy-plane the beams', beam X along its x from the -x side,
    beam Y along its y, crossing at its origin); pin_radius_mm: the calibrated pin's; circle_mm: the
    circles' radius; depths_mm: the guessed tip below the beams' plane on each circle; clearance_mm: the
    tip search starts this far above the plane and ends as far below; offset_max_mm: how far the true tip
    and axis may lie from [cell.tool] (the circles must cross both beams; a TCP found farther is not
    written); circle_speed_mm_s, search_speed_mm_s: the TCP's speed on the circles and in the search;
    beam_x, beam_y: each sensor's switching output, per target (an input number or name); production_tool:
    per target, the tool the production programs use, which gets the TCP found (a numbered tool's number
    where the target's [program.laser] production_tool form is "number", else the name of the production data:
    a task's persistent tooldata, an installation variable; a target with numbered tools may leave it to
    [cell.tool] numbered); safe_height_mm: the safe pose's
    height above the beams' plane (S's z), straight above the circles' start: the way in and the way out; runs: the
    measurements (circles and search) one program makes, whose mean it writes; spread_max_mm: how far each run's
    TCP may lie from that mean (farther: not written); reference_tcp_mm, reference_radius_mm: the reference pin of
    the setup run that measures the sensor frame (None: no setup program)."""

    sensor_frame: TaughtPose
    pin_radius_mm: float
    circle_mm: float
    depths_mm: tuple[float, float]
    clearance_mm: float
    offset_max_mm: float
    circle_speed_mm_s: float
    search_speed_mm_s: float
    beam_x: dict
    beam_y: dict
    production_tool: dict
    safe_height_mm: float
    runs: int = 3
    spread_max_mm: float = 0.1
    reference_tcp_mm: tuple[float, float, float] | None = None
    reference_radius_mm: float = 1.5


def parse_laser(ctx, data: dict, targets, pose_format: str) -> Laser | None:
    """[laser]: its keys as declared (keys.py), then the rules between them and the cell's targets."""
    if "laser" not in data:
        return None
    values = Loader(ctx, pose_format, tuple(targets)).table(LASER, data["laser"], "laser")
    radius, circle, offset = values["pin_radius_mm"], values["circle_mm"], values["offset_max_mm"]
    clearance, depths = values["clearance_mm"], values["depths_mm"]
    if not depths[0] < depths[1]:
        ctx.fail("laser.depths_mm", "expected [d1, d2] with d1 < d2: the guessed tip below the beams, deeper second")
    if depths[1] - depths[0] < DEPTH_STEP_MIN_MM:
        ctx.fail(
            "laser.depths_mm",
            f"d2 - d1 must be at least {DEPTH_STEP_MIN_MM:g} mm: the axis is the centres' difference over it, a "
            "smaller step multiplies their errors",
        )
    # the circle starts at 45 deg between the beams and must cross each twice: the axis may lie offset_max_mm
    # from where the tool's data puts it, and the pin is radius_mm wide
    if offset + radius >= circle / math.sqrt(2.0):
        ctx.fail(
            "laser.circle_mm",
            f"must exceed sqrt(2) (offset_max_mm + pin_radius_mm) = {math.sqrt(2.0) * (offset + radius):.3f} mm: "
            "the circle starts between the beams and must cross each of them twice",
        )
    if clearance <= offset:
        ctx.fail("laser.clearance_mm", f"must exceed offset_max_mm ({offset:g}): the search must start above the tip")
    if depths[0] <= offset + radius:
        ctx.fail(
            "laser.depths_mm",
            f"d1 must exceed offset_max_mm + pin_radius_mm ({offset + radius:g} mm): "
            "the circles must see the pin's side, not its end",
        )
    for target in targets:
        if not KIND.facts(get_target(target)).get("files"):
            ctx.fail(
                "laser",
                f"codegen has no laser TCP program for {get_target(target).title}: take {target} out "
                "of cell.targets for this cell",
            )
    circle_speed = values["circle_speed_mm_s"]
    for target in targets:
        x, y = values["beam_x"][target], values["beam_y"][target]
        if str(x).upper() == str(y).upper():  # a named signal's name ignores case (RAPID)
            ctx.fail(f"laser.beam_y.{target}", "must differ from beam_x: one input per sensor")
        cycle = float(get_target(target).program["signal_cycle_s"])
        if circle_speed * cycle > radius / 2:
            ctx.fail(
                "laser.circle_speed_mm_s",
                f"{target} sees its inputs every {cycle * 1000:g} ms: at {circle_speed:g} mm/s the pin moves "
                f"{circle_speed * cycle:.3f} mm between two looks, more than half its radius: slow the circles",
            )
    if values["safe_height_mm"] < clearance + offset:
        ctx.fail(
            "laser.safe_height_mm",
            f"must be at least clearance_mm + offset_max_mm ({clearance + offset:g} mm): the safe pose lies above "
            "every pose of the calibration",
        )
    reference_radius = values["reference_radius_mm"]
    if values["reference_tcp_mm"] is not None and circle / 2 + reference_radius + offset >= circle:
        ctx.fail(
            "laser.reference_radius_mm",
            f"the setup run's circles about (circle_mm / 2, 0) and (0, circle_mm / 2) must cross both beams with "
            f"offset_max_mm to spare: circle_mm / 2 + reference_radius_mm + offset_max_mm must stay below circle_mm "
            f"({circle:g} mm)",
        )
    _check_production_tools(ctx, values["production_tool"] or {}, targets)
    return build(Laser, values, production_tool=values["production_tool"] or {})


def _check_production_tools(ctx, tools: dict, targets) -> None:
    """[laser] production_tool = { <target> = n or name }, read by its declaration (the target's form of it,
    [program.laser] production_tool): a target of the cell's, a name the program may use."""
    ctx.no_unknown(tools, set(targets), "laser.production_tool")
    for target_name, value in tools.items():
        path = f"laser.production_tool.{target_name}"
        target = get_target(target_name)
        if KIND.facts(target)["production_tool"]["form"] == "number":
            continue
        keywords = get_dialect(target.dialect).keywords()
        if len(value) > target.identifier_max or value.upper() in keywords or value in keywords:
            ctx.fail(
                path,
                f"expected the name of the production tool's data ({target.identifier_max} characters at most; "
                f"not a word {target.title} reserves), got {value!r}",
            )
        if value.lower().startswith(OWN_PREFIX):
            ctx.fail(path, f"must not start with {OWN_PREFIX}: the calibration program's own names do")


def check_production_tools(ctx, laser: Laser, robot, targets) -> None:
    """Every target of the cell names its production tool, here or (a target with numbered tools) as
    [cell.tool] numbered, the same one where both are given: the programs that use the cell's tool use that one."""
    numbered = robot.tool.numbered if robot is not None else {}
    for target in targets:
        given, number = laser.production_tool.get(target), numbered.get(target)
        if given is None and number is None:
            ctx.fail(
                f"laser.production_tool.{target}",
                "missing: the tool the production programs use, which gets the TCP found",
            )
        if given is not None and number is not None and given != number:
            ctx.fail(
                f"laser.production_tool.{target}",
                f"must be cell.tool.numbered.{target} ({number}): the cell's programs use that tool",
            )


def production_tool(cell, target_name: str):
    """The production tool of a target: its number or its name ([laser] production_tool, else the cell's
    numbered tool)."""
    laser = laser_of(cell)
    given = laser.production_tool.get(target_name)
    return given if given is not None else cell.robot.tool.numbered[target_name]


def laser_of(cell) -> Laser | None:
    """A cell's [laser] station, or None."""
    return cell.sections.get("laser")
