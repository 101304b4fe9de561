"""The laser program's error budget: how far off its edges, centres, axis, hits and TCP may be (the model, not a
fit), and what each target's program can meet of the calibration's goal."""

from __future__ import annotations

import math
from dataclasses import dataclass

from codegen.controllers import get_target
from codegen.kinds.laser.section import laser_of

TRUTH_MM = 0.1  # the goal: the TCP found within 0.1 mm of the true one (a requirement, not a model bound)
FLOAT32_MM = 0.002  # float32 positions near 1 m (1.2e-4 mm a step) through a handful of operations


@dataclass(frozen=True)
class Tolerances:
    """From the model: an edge is seen up to one controller cycle late (the TCP then a cycle's travel on)
    and its switching point moves by the noise (6 sigma); the centres are means of edges; the axis is their
    difference over the depths' step; the search runs along the program's own axis, which lies off the
    reference's by the centre's and the axis's errors."""

    edge: float
    centre: float
    axis: float
    hit: float
    tcp: float


def tolerances(cell, target, noise: float) -> Tolerances:
    laser = laser_of(cell)
    cycle = float(target.program["signal_cycle_s"])
    edge = laser.circle_speed_mm_s * cycle + 6 * noise + FLOAT32_MM
    # a centre is the mean of four edges, two crossings run in opposite directions: each edge is late by up to
    # a cycle's travel along its crossing's direction, so the mean by up to half of it; the noise of a mean of
    # four is half an edge's
    centre = laser.circle_speed_mm_s * cycle / 2 + 3 * noise + FLOAT32_MM
    axis = 2 * centre / (laser.depths_mm[1] - laser.depths_mm[0])
    local = laser.search_speed_mm_s * cycle + 6 * noise  # a hit along the program's own search line
    hit = local + centre + axis * (laser.depths_mm[0] + laser.clearance_mm)  # that line off the reference's
    # the contact is the mean of the down hit (late: lower) and the up hit (late: higher): half a cycle's
    # travel, the noise of a mean of two; that line off the true axis by the centre's error (the tip is taken
    # on the axis through S's origin); the rim's term through the axis (rho times its error)
    contact = laser.search_speed_mm_s * cycle / 2 + 6 * noise / math.sqrt(2)
    tcp = contact + centre + laser.pin_radius_mm * axis + FLOAT32_MM
    return Tolerances(edge, centre, axis, hit, tcp)


def check_goal(ctx, cell) -> None:
    """What the model (tolerances, the sensors' noise aside) says each target's program can meet: the TCP
    within the TRUTH_MM goal, and offset_max_mm and spread_max_mm above the TCP's error (a correct tool found farther
    than offset_max_mm from the tool as designed stops as too far, runs farther apart than spread_max_mm as not
    repeatable); spread_max_mm at most offset_max_mm."""
    laser = laser_of(cell)
    for name in cell.targets:
        target = get_target(name)
        cycle = float(target.program["signal_cycle_s"])
        tcp = tolerances(cell, target, 0.0).tcp
        reads = f"{name} reads its inputs every {cycle * 1000:g} ms"
        if tcp > TRUTH_MM:
            contact = laser.search_speed_mm_s * cycle / 2  # the search's term of the TCP's error
            room = TRUTH_MM - (tcp - contact)
            if room <= 0:
                ctx.fail(
                    "laser.circle_speed_mm_s",
                    f"{reads}: at {laser.circle_speed_mm_s:g} mm/s the circles' centres alone put the TCP up to "
                    f"{tcp - contact:.3f} mm off, beyond the {TRUTH_MM:g} mm goal: slow the circles",
                )
            ctx.fail(
                "laser.search_speed_mm_s",
                f"{reads}: at {laser.search_speed_mm_s:g} mm/s the tip search sees the tip up to "
                f"{laser.search_speed_mm_s * cycle:.3f} mm late, and the TCP may be {tcp:.3f} mm off, beyond the "
                f"{TRUTH_MM:g} mm goal: at most {room / (cycle / 2):.3g} mm/s here",
            )
        if laser.offset_max_mm < tcp:
            ctx.fail(
                "laser.offset_max_mm",
                f"{reads}: it finds a correct tool's TCP up to {tcp:.3f} mm off (the circles' and the search's "
                f"speeds): an offset_max_mm below that stops a correct tool as too far",
            )
        if laser.spread_max_mm < tcp:
            ctx.fail(
                "laser.spread_max_mm",
                f"{reads}: each run finds a correct tool's TCP up to {tcp:.3f} mm off: a spread_max_mm below that "
                "stops a correct tool as not repeatable",
            )
    if laser.spread_max_mm > laser.offset_max_mm:
        ctx.fail(
            "laser.spread_max_mm",
            f"must be at most offset_max_mm ({laser.offset_max_mm:g}): each run's TCP lies within it of the tool as "
            "designed",
        )
