"""The station kind's math in sympy: the correction transform of source 000, derived and proven with its errata,
and the frame refinement of source 001.

The identities are proven with the check codegen/derivation.py passes in (check(name, statement, expected,
residual[, fixed]) -> Identity): this module does not import it, it is imported by it."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import sympy as sp

from codegen import protocol
from codegen.symrot import rot2, rotx3, roty3, rotz3

# Symbols, named after the frames they belong to (the point mode's page of the docs).
# t = calibration mark (tx, ty, t_theta), tn = current mark, P = taught pose, Pn = corrected pose.
tx, ty, t_theta = sp.symbols("tx ty t_theta", real=True)
tnx, tny = sp.symbols("tnx tny", real=True)
phi = sp.Symbol("phi", real=True)  # rotation of the mark since calibration, already signed
Px, Py, Pz = sp.symbols("Px Py Pz", real=True)
Pnx, Pny = sp.symbols("Pnx Pny", real=True)
a, b, c = sp.symbols("a b c", real=True)  # Euler Z-Y-X angles of a taught orientation

P = sp.Matrix([Px, Py])
t = sp.Matrix([tx, ty])
tn = sp.Matrix([tnx, tny])


@dataclass(frozen=True)
class Derivation:
    invariance: sp.Matrix  # the equations solved (== 0)
    Pn: sp.Matrix  # corrected position (x, y)
    D: sp.Matrix  # 3x3 planar homogeneous transform, Pn = D * [P; 1]


@cache  # proved once per process
def derive() -> Derivation:
    """Solve R(t_theta)^T (P - t) = R(t_theta + phi)^T (Pn - tn) for Pn, then read D off Pn."""
    mark_now_theta = t_theta + phi
    invariance = rot2(t_theta).T * (P - t) - rot2(mark_now_theta).T * (sp.Matrix([Pnx, Pny]) - tn)
    solutions = sp.solve(list(invariance), [Pnx, Pny], dict=True)
    if len(solutions) != 1:
        raise RuntimeError(f"expected one solution of the invariance, got {len(solutions)}")
    sol = solutions[0]
    Pn = sp.Matrix([sp.simplify(sp.expand_trig(sol[Pnx])), sp.simplify(sp.expand_trig(sol[Pny]))])
    # D: the rotation block is the Jacobian of Pn in P, the translation is Pn at P = 0.
    jac = Pn.jacobian(P).applyfunc(sp.simplify)
    offset = Pn.subs({Px: 0, Py: 0}).applyfunc(sp.simplify)
    D = sp.Matrix.vstack(sp.Matrix.hstack(jac, offset), sp.Matrix([[0, 0, 1]]))
    return Derivation(invariance=invariance, Pn=Pn, D=D)


FREE = (tx, ty, t_theta, tnx, tny, phi, Px, Py, a, b, c)  # every counterexample search draws these


@cache  # on the derivation, itself once per process: proved once per process
def point_identities(check) -> list:
    """Source 000's correction and its errata, proven on the derivation."""
    d = derive()
    Pn = d.Pn
    result = []

    result.append(
        check(
            "zero_rotation_is_translation",
            "phi = 0: Pn = P + (tn - t)   (source eq. 16)",
            "holds",
            Pn.subs(phi, 0) - (P + tn - t),
        )
    )
    result.append(
        check(
            "rigid",
            "|Pn - tn|^2 = |P - t|^2",
            "holds",
            (Pn - tn).dot(Pn - tn) - (P - t).dot(P - t),
        )
    )
    mark_dir = sp.Matrix([sp.cos(t_theta), sp.sin(t_theta), 0])
    mark_dir_now = sp.Matrix([sp.cos(t_theta + phi), sp.sin(t_theta + phi), 0])
    result.append(
        check(
            "mark_maps_to_mark",
            "D t = tn and D turns the mark direction t_theta to t_theta + phi",
            "holds",
            sp.Matrix.vstack(
                d.D * sp.Matrix([tx, ty, 1]) - sp.Matrix([tnx, tny, 1]),
                d.D * mark_dir - mark_dir_now,
            ),
        )
    )
    result.append(
        check(
            "yaw_addition",
            "Rz(phi) Rz(a) Ry(b) Rx(c) = Rz(a + phi) Ry(b) Rx(c)",
            "holds",
            rotz3(phi) * rotz3(a) * roty3(b) * rotx3(c) - rotz3(a + phi) * roty3(b) * rotx3(c),
        )
    )
    # Source 000 eq. 6/13: ax = Px - tnx, Pn = tn + R(ac)(P - tn).
    eq13 = tn + rot2(phi) * (P - tn)
    result.append(
        check(
            "source_eq13",
            "Pn = tn + R(phi)(P - tn)   (source eq. 13; at phi = 0 it gives P, eq. 15)",
            "refuted",
            eq13 - Pn,
        )
    )
    result.append(
        check(
            "source_eq13_rigid",
            "source eq. 13 keeps |Pn - tn| = |P - t|",
            "refuted",
            (eq13 - tn).dot(eq13 - tn) - (P - t).dot(P - t),
        )
    )

    # Source 000 listing: ax = p[0] - markp.x; px = ax cos(ac) - ay sin(ac) + tx.
    def listing(markp: sp.Matrix, txy: sp.Matrix) -> sp.Matrix:
        return rot2(phi) * (P - markp) + txy

    result.append(
        check(
            "source_listing_as_named",
            "listing with markp = current mark, tx,ty = calibration mark",
            "refuted",
            listing(tn, t) - Pn,
        )
    )
    result.append(
        check(
            "source_listing_names_swapped",
            "listing with markp = calibration mark, tx,ty = current mark",
            "holds",
            listing(t, tn) - Pn,
        )
    )
    # Listing orientation: rz = p[5] - ac while the position turns by +ac.
    result.append(
        check(
            "source_listing_orientation_sign",
            "Rz(phi) Rz(a) = Rz(a - phi)   (listing's rz = p[5] - ac)",
            "refuted",
            rotz3(phi) * rotz3(a) - rotz3(a - phi),
        )
    )
    return result


# --- frame correction with refinement (source 001) --------------------------------------------

# The current frame, in the reference frame's coordinates: origin (dx, dy), rotation alpha.
# The true frame (where the mark really is): (dx_true, dy_true, alpha_true).
dx, dy, alpha = sp.symbols("dx dy alpha", real=True)
dx_true, dy_true, alpha_true = sp.symbols("dx_true dy_true alpha_true", real=True)
res_x, res_y, gamma = sp.symbols("res_x res_y gamma", real=True)


def frame_residual() -> tuple[sp.Matrix, sp.Expr]:
    """What the camera riding with the current frame measures: the true frame in the current
    frame's axes, cur2ref^-1 . true2ref = [R(-alpha)(d_true - d) | alpha_true - alpha]."""
    d, d_true = sp.Matrix([dx, dy]), sp.Matrix([dx_true, dy_true])
    return rot2(-alpha) * (d_true - d), alpha_true - alpha


def frame_update(sign: int = 1) -> tuple[sp.Matrix, sp.Expr]:
    """New frame from a residual (res_x, res_y, gamma) measured in the current frame's axes: the
    residual is turned into the reference frame by R(sign * alpha) (source 001 eq. 6-7 print -1)."""
    d = sp.Matrix([dx, dy])
    return d + rot2(sign * alpha) * sp.Matrix([res_x, res_y]), alpha + gamma


@cache  # independent of the derivation: proved once per process
def frame_identities(check) -> list:
    measured, measured_gamma = frame_residual()
    at_measurement = {res_x: measured[0], res_y: measured[1], gamma: measured_gamma}
    d_true = sp.Matrix([dx_true, dy_true])
    out = []
    new_d, new_alpha = frame_update(+1)
    out.append(
        check(
            "frame_update",
            "d' = d + R(+alpha) [res_x, res_y], alpha' = alpha + gamma reaches the true frame in one step",
            "holds",
            sp.Matrix.vstack(
                new_d.subs(at_measurement) - d_true, sp.Matrix([new_alpha.subs(at_measurement) - alpha_true])
            ),
        )
    )
    printed_d, _ = frame_update(-1)
    out.append(
        check(
            "source_frame_update",
            "source 001 eq. 6: d' = d + R(-alpha) [res_x, res_y] reaches the true frame",
            "refuted",
            printed_d.subs(at_measurement) - d_true,
            fixed={alpha: sp.Rational(1, 3)},
        )
    )
    # Contraction of the position error with the printed sign: e' = (I - R(-2 alpha)) e.
    error, error_next = d_true - sp.Matrix([dx, dy]), d_true - printed_d.subs(at_measurement)
    ratio = sp.simplify(sp.expand_trig(error_next.dot(error_next) / error.dot(error)))
    out.append(
        check(
            "source_frame_update_contraction",
            "with the printed sign |e'|^2 / |e|^2 = (2 sin(alpha))^2",
            "holds",
            ratio - (2 * sp.sin(alpha)) ** 2,
        )
    )
    return out


def source_frame_contraction() -> sp.Expr:
    """|e'| / |e| for the printed update, derived (not typed): 2 |sin(alpha)|."""
    printed_d, _ = frame_update(-1)
    measured, _g = frame_residual()
    d_true = sp.Matrix([dx_true, dy_true])
    error_next = d_true - printed_d.subs({res_x: measured[0], res_y: measured[1]})
    error = d_true - sp.Matrix([dx, dy])
    return sp.sqrt(sp.simplify(sp.expand_trig(error_next.dot(error_next) / error.dot(error))))


def printed_blocks() -> dict[str, dict[str, sp.Expr]]:
    """The closed forms the controllers evaluate: D ("frame") and Pn ("point") from tx, ty, tnx, tny, Px, Py and
    phi; the refined frame ("refine") from dx, dy, alpha and the residual."""
    d = derive()
    trig = [sp.cos(phi), sp.sin(phi)]
    # Grouped by cos/sin so that (P - t) is formed first: less cancellation in float32.
    new_d, _new_alpha = frame_update(+1)
    return {
        "frame": {
            "frame_cos": d.D[0, 0],
            "frame_sin": d.D[1, 0],
            "frame_x": sp.collect(sp.expand(d.D[0, 2]), trig),
            "frame_y": sp.collect(sp.expand(d.D[1, 2]), trig),
        },
        "point": {
            "point_x": sp.collect(sp.expand(d.Pn[0]), trig),
            "point_y": sp.collect(sp.expand(d.Pn[1]), trig),
        },
        "refine": {"new_dx": new_d[0], "new_dy": new_d[1]},
    }


def describe() -> str:
    d = derive()
    lines = [
        "Invariance of the mark-relative coordinates (solved for Pnx, Pny):",
        f"  R(t_theta)^T (P - t) - R(t_theta + phi)^T (Pn - tn) = {sp.sstr(list(d.invariance))} = 0",
        "Solution:",
        f"  Pnx = {sp.sstr(d.Pn[0])}",
        f"  Pny = {sp.sstr(d.Pn[1])}",
        "Correction transform D (Pn = D [P; 1]):",
    ]
    lines += [f"  {sp.sstr(list(d.D.row(i)))}" for i in range(3)]
    lines.append("phi = angle_sign * wrap(tn_theta - t_theta), applied once; orientation turns by phi.")
    measured, measured_gamma = frame_residual()
    new_d, new_alpha = frame_update(+1)
    printed_d, _ = frame_update(-1)
    lines += [
        "",
        "Frame refinement (source 001): the current frame is (d, alpha) in the reference frame; the camera",
        "rides with it and measures the true frame in the current frame's axes:",
        f"  [res_x, res_y] = {sp.sstr(list(measured))}, gamma = {sp.sstr(measured_gamma)}",
        "Update (turned into the reference frame by R(+alpha)):",
        f"  d' = {sp.sstr(list(new_d))}, alpha' = {sp.sstr(new_alpha)}",
        f"Source 001 eq. 6 prints R(-alpha): d' = {sp.sstr(list(printed_d))};",
        f"  its position error contracts by |e'|/|e| = {sp.sstr(source_frame_contraction())} per photo"
        " (diverges for |alpha| > 30 deg).",
    ]
    return "\n".join(lines)


def symbols() -> dict:
    """The conventions of codegen.derivation's proof and printing for this math: phi a small angle, and the
    common subexpressions printed by name."""
    return {
        "free": FREE,
        "small": (phi,),
        "readable": {
            sp.cos(phi): "cos_phi",
            sp.sin(phi): "sin_phi",
            Px - tx: "ax",
            Py - ty: "ay",
            sp.cos(alpha): "cos_alpha",
            sp.sin(alpha): "sin_alpha",
        },
    }


class DerivationPart(protocol.Derivation):
    """Source 000's correction and source 001's frame refinement, derived and proved."""

    def derive(self) -> Derivation:
        return derive()

    def describe(self, derivation) -> str:
        return describe()

    def identities(self, check) -> list:
        return [*point_identities(check), *frame_identities(check)]

    def symbols(self) -> dict:
        return symbols()

    def printed_blocks(self) -> dict:
        return printed_blocks()
