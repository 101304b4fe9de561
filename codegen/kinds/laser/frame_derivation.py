"""The sensor frame measured with a reference pin: its geometry in sympy, proven (frame_solve.py solves it)."""

# A 0.1 mm error in the sensor frame S the cell names passes whole into every TCP the calibration finds
# (docs/kinds/laser.md). A setup run measures where the beams really are with a reference pin of known geometry
# (a TCP known to better than the goal, its axis along the flange's z): the program moves it with its axis along
# the named S's z (vertical in S) and reads the beams' edges exactly as the calibration does, so what it finds
# describes the beams, not the pin.
#
# The beams in the named S: both pass through the crossing d; beam X runs along b = (bx, by, bz), beam Y along
# a = (ax, ay, az) (bx > 0, ay > 0). Their yaws tX = by / bx and tY = ax / ay, their slopes sX = bz / |(bx, by)| and
# sY = az / |(ax, ay)|. The measurement:
# 1. Circles of the pin's axis (radius r) about c = (0, 0), (delta, 0) and (0, delta): the mean of beam X's four
#    edges is the midpoint of the chord the beam's vertical plane cuts from the circle (the edges lie at +-w from the
#    plane, w the pin's radius and the hysteresis: they cancel), whose y is
#        yX(c) = cy + ((cx - dx) tX - (cy - dy)) / (1 + tX^2)
#    (`laser_frame_chord`), and beam Y's likewise xY(c) with the roles of x and y swapped. The step from (0, 0) to
#    (delta, 0) moves yX by delta tX / (1 + tX^2): tX from that (the root with |tX| <= 1), tY from (0, delta); then
#    d's x and y from the two centres at c = 0, a linear pair with determinant tX tY - 1 (`laser_frame_crossing`).
# 2. Tip searches along the axis down to beam X at two points of it, L either side of the crossing along x: the
#    flat end (horizontal) first meets the sloped beam at its rim, so each contact lies rho |sX| above the beam
#    under the pin's centre; the two contacts' difference over their distance along the beam is sX (the rim's
#    share cancels), their mean dz + rho |sX| (`laser_frame_slope`). Beam Y likewise gives sY.
# Where it breaks (each a check below): delta = 0 (the yaws are not seen); tX tY = 1 (the beams parallel in the
# plane: no crossing); a step along beam X's own direction shows nothing of the beam's height, so the slopes need
# two search points apart along each beam (L > 0); and a pin whose axis is not along S's z (a bent reference) moves
# every centre with the height: the reference's straightness bounds what the setup can find.

from __future__ import annotations

from functools import cache

import sympy as sp

cx, cy, dx, dy, dz = sp.symbols("cx cy dx dy dz", real=True)
tX, tY, delta, L, rho, r = sp.symbols("tX tY delta L rho r", real=True)
sX = sp.Symbol("sX", positive=True)  # the slope's sign is the mirror image
w = sp.Symbol("w", real=True)


def chord_mean_y(cx_, cy_, t) -> sp.Expr:
    """The y of the chord midpoint beam X's vertical plane cuts from the circle about (cx_, cy_)."""
    return cy_ + ((cx_ - dx) * t - (cy_ - dy)) / (1 + t**2)


def _chord_identity(check):
    """The circle's two points at signed distance s from beam X's vertical plane (unit normal n = (tX, -1) /
    sqrt(1 + tX^2) through d, m = (1, tX) / sqrt(1 + tX^2) along it): p = c + (s - (c - d).n) n +- h m with
    h^2 = r^2 - (s - (c - d).n)^2. They lie on the circle and at s from the plane; the four for s = +w and -w (in
    and out, both crossings) average to yX(c), whatever w."""
    n = sp.Matrix([tX, -1]) / sp.sqrt(1 + tX**2)
    m = sp.Matrix([1, tX]) / sp.sqrt(1 + tX**2)
    c, dd = sp.Matrix([cx, cy]), sp.Matrix([dx, dy])
    points = []
    for sign_s in (1, -1):
        off = sign_s * w - (c - dd).dot(n)
        h = sp.sqrt(r**2 - off**2)
        points += [(c + off * n + k * h * m, sign_s * w) for k in (1, -1)]
    residual = [e for p_, s_ in points for e in ((p_ - c).dot(p_ - c) - r**2, (p_ - dd).dot(n) - s_)]
    mean_y = sum(p_[1] for p_, _ in points) / 4
    return check(
        "laser_frame_chord",
        "beam X's four edges on a circle about c average to y = cy + ((cx - dx) tX - (cy - dy)) / (1 + tX^2), "
        "whatever the pin's radius and hysteresis (w)",
        "holds",
        sp.Matrix([*residual, mean_y - chord_mean_y(cx, cy, tX)]),
    )


def _crossing_identity(check):
    """tX from the step in yX (the root with |tX| <= 1), d's x and y from the centres at c = 0; where it breaks."""
    step = chord_mean_y(delta, 0, tX) - chord_mean_y(0, 0, tX)
    k = tX / (1 + tX**2)
    root = (1 - tX**2) / (1 + tX**2)  # sqrt(1 - 4 k^2) where |tX| <= 1
    y0, x0 = chord_mean_y(0, 0, tX), chord_mean_y(0, 0, tY).subs({dx: dy, dy: dx}, simultaneous=True)
    system = sp.Matrix([[-tX, 1], [1, -tY]])
    rhs = sp.Matrix([y0 * (1 + tX**2), x0 * (1 + tY**2)])
    along = sp.Matrix([tY, 1])  # a shift of the crossing that parallel beams do not see
    return [
        check(
            "laser_frame_yaw",
            "the circle moved delta along x moves beam X's centre by delta k, k = tX / (1 + tX^2); "
            "1 - 4 k^2 = ((1 - tX^2) / (1 + tX^2))^2 and tX = (1 - sqrt(1 - 4 k^2)) / (2 k) for |tX| <= 1",
            "holds",
            sp.Matrix([step / delta - k, 1 - 4 * k**2 - root**2, (1 - root) / (2 * k) - tX]),
        ),
        check(
            "laser_frame_crossing",
            "(dx, dy) = [-tX 1; 1 -tY]^-1 (yX(0) (1 + tX^2), xY(0) (1 + tY^2)): the beams' crossing in the plane",
            "holds",
            system.LUsolve(rhs) - sp.Matrix([dx, dy]),
        ),
        check(
            "laser_frame_parallel_beams",
            "where tX tY = 1 (the beams parallel in the plane) a shift of d along (tY, 1) leaves both centres: "
            "the crossing is not determined",
            "holds",
            (system * along).subs(tX, 1 / tY),
        ),
        check(
            "laser_frame_no_step",
            "with the circles at one place (delta = 0) the step does not depend on the yaw: it is not seen",
            "holds",
            sp.Matrix([sp.diff(step, tX).subs(delta, 0)]),
        ),
    ]


def _slope_identity(check):
    """Beam X sloped by sX (height dz + sX t along it, t the distance along it in the plane): a horizontal end face
    of radius rho centred over the beam at t first touches it at its rim, rho sX higher; two contacts at t = -L and
    +L: difference / 2L = sX, mean = dz + rho sX. At L = 0 the difference says nothing of sX."""
    contact = [dz + sX * t + rho * sX for t in (-L, L)]
    return [
        check(
            "laser_frame_slope",
            "two contacts L either side of the crossing along beam X: (z2 - z1) / 2L = sX, (z1 + z2)/2 = dz + rho sX",
            "holds",
            sp.Matrix([(contact[1] - contact[0]) / (2 * L) - sX, (contact[0] + contact[1]) / 2 - dz - rho * sX]),
        ),
        check(
            "laser_frame_one_search_point",
            "with both contacts at one point of the beam (L = 0) their difference does not depend on the slope",
            "holds",
            sp.Matrix([sp.diff(contact[1] - contact[0], sX).subs(L, 0)]),
        ),
    ]


@cache
def frame_identities(check) -> list:
    return [_chord_identity(check), *_crossing_identity(check), *_slope_identity(check)]
