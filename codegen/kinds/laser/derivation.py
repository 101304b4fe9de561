"""Source 003's laser-sensor TCP geometry in sympy: circle centres, the tool axis, the tip, the pin's radius.

Proven with the check codegen/derivation.py passes in, as every kind's derivation."""

# The sensor frame S (docs/kinds/laser.md): the two beams lie in S's xy-plane (z = 0) and cross at right
# angles at its origin; beam X runs along S's x from a sensor on its -x side, beam Y along S's y. The tool
# is a pin of radius rho about its axis, direction u = (ux, uy, uz) in S (unit, uz > 0: from the tip up).
# Moved with a fixed orientation, the flange carries the axis without turning it: on a horizontal circle
# of radius r the axis meets the beams' plane on a circle of radius r about a centre c.

from __future__ import annotations

from functools import cache

import sympy as sp

from codegen import protocol
from codegen.kinds.laser.frame_derivation import frame_identities

cx, cy, cz = sp.symbols("cx cy cz", real=True)  # the circle's centre (where the axis meets z = 0), mm
r, rho, dz = sp.symbols("r rho dz", positive=True)  # circle radius, pin radius, height step of the flange
ux, uy = sp.symbols("ux uy", real=True)
uz = sp.sqrt(1 - ux**2 - uy**2)  # u is a unit vector pointing up
x, d, lam, s = sp.symbols("x d lam s", real=True)
ax, ay, az = sp.symbols("ax ay az", real=True)  # a point of the axis, S


def crossings() -> list:
    """Where the axis point's circle (x - cx)^2 + (y - cy)^2 = r^2 crosses beam X (y = 0), solved."""
    return sp.solve(sp.Eq((x - cx) ** 2 + cy**2, r**2), x)


def near_surface_offset() -> sp.Expr:
    """How far before the axis beam X meets the pin's surface when the axis crosses the beam: the beam
    line's points at (d, 0, 0) from the axis point lie |d| sqrt(1 - ux^2) from the axis."""
    return -rho / sp.sqrt(1 - ux**2)


def plane_point(point: sp.Matrix) -> sp.Matrix:
    """Where the axis through `point` (direction u) meets the beams' plane z = 0."""
    u = sp.Matrix([ux, uy, uz])
    return point - (point[2] / uz) * u


def rim_identity(check):
    """A tilted pin's flat end meets beam X with its rim: the end face's points in the beam's vertical
    plane (y = 0 through the tip) lie along v = (uz, 0, -ux) / |(ux, uz)| (in the face: v . u = 0, unit),
    so its lowest one is rho ux / |(ux, uz)| below the tip (ux > 0; likewise beam Y with uy)."""
    tilt = sp.Symbol("tilt_x", positive=True)  # ux > 0 (the other sign is the mirror image)
    u = sp.Matrix([tilt, uy, sp.sqrt(1 - tilt**2 - uy**2)])
    v = sp.Matrix([u[2], 0, -tilt]) / sp.sqrt(tilt**2 + u[2] ** 2)
    return check(
        "laser_tip_rim",
        "a beam first meets a tilted pin's end at its rim, rho |ux| / |(ux, uz)| below the tip (not the tip)",
        "holds",
        sp.Matrix([v.dot(u), v.dot(v) - 1, rho * v[2] + rho * tilt / sp.sqrt(tilt**2 + u[2] ** 2)]),
    )


def tip_on_beam_identity(check):
    """The search's contact, exactly (codegen/kinds/laser/program.py): the axis through the beams' crossing (S's
    origin), the tip T = lam u. The end face (points T + w, w . u = 0, |w| <= rho) meets beam X (y = 0, z = 0)
    where w = (lam (1 - ux^2) / ux, -lam uy, -lam uz) (the only point of the face's plane on the beam), so it
    first touches the beam at |w| = rho: lam = rho ux / sqrt(1 - ux^2), the tip rho ux uz / sqrt(1 - ux^2)
    above the plane (ux > 0; the other sign is the mirror image)."""
    tilt = sp.Symbol("tilt_x", positive=True)
    u = sp.Matrix([tilt, uy, sp.sqrt(1 - tilt**2 - uy**2)])
    lam_c = rho * tilt / sp.sqrt(1 - tilt**2)
    w = sp.Matrix([lam_c * (1 - tilt**2) / tilt, -lam_c * uy, -lam_c * u[2]])
    point = lam_c * u + w
    return check(
        "laser_tip_on_beam",
        "with the axis through the crossing, beam X first meets the end face when the tip is "
        "rho |ux| uz / sqrt(1 - ux^2) above the plane (the face's point on the beam at rho from the tip)",
        "holds",
        sp.Matrix([w.dot(u), w.dot(w) - rho**2, point[1], point[2]]),
    )


def edge_identity(check):
    """What the programs use instead of the readings (codegen/kinds/laser/program.py): beam X (the line y = 0 of
    the plane) meets the pin while the axis point's y lies within w = rho sqrt(1 - ux^2) / uz of it: the
    smallest squared distance from the beam's points (X, 0, 0) to the axis through (0, ay, 0) is
    ay^2 uz^2 / (1 - ux^2), even in ay. So a crossing's two edges lie at ay = -+(w -+ h/2) (h: the sensor's
    hysteresis: on at w - h/2, off at w + h/2), and the four edges of the two crossings (opposite directions)
    average to ay = 0: the pin's radius and the hysteresis cancel; the centre is minus the edges' mean."""
    X, w, h = sp.symbols("X w h", real=True)  # X: a point of the beam
    d = sp.Matrix([X, -ay, 0])
    u = sp.Matrix([ux, uy, uz])
    f = d.dot(d) - d.dot(u) ** 2
    at = sp.solve(sp.diff(f, X), X)[0]
    smallest = f.subs(X, at) - ay**2 * uz**2 / (1 - ux**2)
    edges = [-(w - h / 2), w + h / 2, w - h / 2, -(w + h / 2)]  # in, out (moving +y); in, out (moving -y)
    return check(
        "laser_edges_centre",
        "beam X meets the pin while |ay| <= rho sqrt(1 - ux^2) / uz (the distance's minimum is even in ay): "
        "the four edges of two opposite crossings average to the axis point, whatever rho and the hysteresis h",
        "holds",
        sp.Matrix([smallest, sum(edges) / 4]),
    )


@cache  # independent of the correction's derivation: proved once per process
def laser_identities(check) -> list:
    u = sp.Matrix([ux, uy, uz])
    low, high = crossings()
    mean = (low + high) / 2
    offset = near_surface_offset()
    distance_sq = (sp.Matrix([offset, 0, 0]).cross(u)).dot(sp.Matrix([offset, 0, 0]).cross(u))
    axis_point = sp.Matrix([ax, ay, az])
    c1 = plane_point(axis_point)
    c2 = plane_point(axis_point + sp.Matrix([0, 0, dz]))  # the flange raised by dz, the same orientation
    stepped = axis_point - lam * u  # the flange stepped down the axis by lam
    raw = (low + offset + high + offset) / 2  # the two readings' mean, as the source takes it
    return [
        check(
            "laser_circle_centre",
            "the circle crosses beam X at x1, x2 (solved): (x1 + x2)/2 = cx   (source 003; likewise beam Y: cy)",
            "holds",
            mean - cx,
        ),
        check(
            "laser_surface_at_crossing",
            "as the axis crosses beam X, the beam meets the pin's surface rho / sqrt(1 - ux^2) before the axis",
            "holds",
            distance_sq - rho**2,
        ),
        check(
            "source_laser_centre_from_readings",
            "the readings' mean (x1' + x2')/2 is the circle's centre cx   (source 003: the sensor sees the "
            "pin's surface, not its axis; pin radius 1.5 mm)",
            "refuted",
            raw - cx,
            fixed={rho: sp.Rational(3, 2), ux: 0, cy: 1, r: 20},
        ),
        check(
            "laser_centre_corrected_for_the_pin",
            "(x1' + x2')/2 + rho / sqrt(1 - ux^2) = cx   (the readings' centre corrected for the pin's radius)",
            "holds",
            raw - offset - cx,
        ),
        check(
            "laser_axis_from_two_centres",
            "the flange raised by dz moves the axis point by -dz (ux, uy)/uz: (c1 - c2)/dz = (ux/uz, uy/uz), "
            "whatever offset both centres share (the pin's radius cancels)",
            "holds",
            sp.Matrix([(c1[0] - c2[0]) / dz - ux / uz, (c1[1] - c2[1]) / dz - uy / uz, c2[2]]),
        ),
        check(
            "laser_step_keeps_the_axis",
            "stepping the flange along u moves the axis along itself: the tip meets z = 0 at the axis point c",
            "holds",
            sp.Matrix.vstack((stepped - axis_point).cross(u), plane_point(stepped) - c1),
        ),
        rim_identity(check),
        edge_identity(check),
        tip_on_beam_identity(check),
        check(
            "source_laser_tip_uncorrected",
            "with the axis put at the readings' centre (uncorrected), the beams pass through the pin's axis "
            "(each passes rho from it, shifted by the other beam's offset: it only grazes the pin; 1.5 mm)",
            "refuted",
            sp.sqrt(distance_sq),
            fixed={rho: sp.Rational(3, 2), ux: sp.Rational(1, 10), uy: sp.Rational(1, 10)},
        ),
    ]


class DerivationPart(protocol.Derivation):
    def identities(self, check) -> list:
        return laser_identities(check) + frame_identities(check)
