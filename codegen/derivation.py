"""Symbolic derivation of the correction transform and proof of its identities (sympy: here and in the kinds)."""

from __future__ import annotations

import json
import random
import sys
from dataclasses import dataclass
from functools import cache

import sympy as sp

from codegen.derived import CACHE_PATH
from codegen.dialects import printers
from codegen.protocol import kinds
from codegen.symrot import rot2, rotx3, roty3, rotz3

# Symbols, named after the frames they belong to (DESIGN.md section 1.1).
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


# --- identities ------------------------------------------------------------------------------


@dataclass(frozen=True)
class Identity:
    name: str
    statement: str
    expected: str  # "holds" or "refuted"
    status: str  # "holds", "refuted" or "unproven"
    detail: str

    @property
    def as_expected(self) -> bool:
        return self.status == self.expected


_FREE = [tx, ty, t_theta, tnx, tny, phi, Px, Py, a, b, c]  # extended below for the frame symbols


def _simplify_zero(expr) -> bool:
    expr = sp.Matrix(expr) if isinstance(expr, sp.MatrixBase) else sp.Matrix([expr])
    return all(sp.simplify(sp.expand_trig(sp.expand(e))) == 0 for e in expr)


def _counterexample(expr, fixed: dict | None = None, seed: int = 7) -> str | None:
    """A rational point where expr is visibly non-zero (|value| > 1e-6), or None."""
    rng = random.Random(seed)
    expr = sp.Matrix(expr) if isinstance(expr, sp.MatrixBase) else sp.Matrix([expr])
    free = sorted(set().union(*(e.free_symbols for e in expr)) | set(_FREE), key=str)
    for _ in range(20):
        point = {s: sp.Rational(rng.randint(-900, 900), 10) for s in free}
        point[phi] = sp.Rational(rng.randint(-300, 300), 1000)
        if fixed:
            point.update(fixed)
        values = [sp.N(e.subs(point)) for e in expr]
        worst = max(abs(v) for v in values)
        if worst > 1e-6:
            shown = ", ".join(f"{k}={point[k]}" for k in free if expr.has(k))
            return f"at {shown}: residual {sp.N(worst, 6)}"
    return None


def _check(name: str, statement: str, expected: str, residual, fixed: dict | None = None) -> Identity:
    if _simplify_zero(residual):
        return Identity(name, statement, expected, "holds", "residual simplifies to 0")
    witness = _counterexample(residual, fixed)
    if witness is not None:
        return Identity(name, statement, expected, "refuted", witness)
    return Identity(name, statement, expected, "unproven", "not simplified to 0, no counterexample")


def identities(derivation: Derivation | None = None) -> list[Identity]:
    d = derivation or derive()
    Pn = d.Pn
    result = []

    result.append(
        _check(
            "zero_rotation_is_translation",
            "phi = 0: Pn = P + (tn - t)   (source eq. 16)",
            "holds",
            Pn.subs(phi, 0) - (P + tn - t),
        )
    )
    result.append(
        _check(
            "rigid",
            "|Pn - tn|^2 = |P - t|^2",
            "holds",
            (Pn - tn).dot(Pn - tn) - (P - t).dot(P - t),
        )
    )
    mark_dir = sp.Matrix([sp.cos(t_theta), sp.sin(t_theta), 0])
    mark_dir_now = sp.Matrix([sp.cos(t_theta + phi), sp.sin(t_theta + phi), 0])
    result.append(
        _check(
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
        _check(
            "yaw_addition",
            "Rz(phi) Rz(a) Ry(b) Rx(c) = Rz(a + phi) Ry(b) Rx(c)",
            "holds",
            rotz3(phi) * rotz3(a) * roty3(b) * rotx3(c) - rotz3(a + phi) * roty3(b) * rotx3(c),
        )
    )
    # Source 000 eq. 6/13: ax = Px - tnx, Pn = tn + R(ac)(P - tn).
    eq13 = tn + rot2(phi) * (P - tn)
    result.append(
        _check(
            "source_eq13",
            "Pn = tn + R(phi)(P - tn)   (source eq. 13; at phi = 0 it gives P, eq. 15)",
            "refuted",
            eq13 - Pn,
        )
    )
    result.append(
        _check(
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
        _check(
            "source_listing_as_named",
            "listing with markp = current mark, tx,ty = calibration mark",
            "refuted",
            listing(tn, t) - Pn,
        )
    )
    result.append(
        _check(
            "source_listing_names_swapped",
            "listing with markp = calibration mark, tx,ty = current mark",
            "holds",
            listing(t, tn) - Pn,
        )
    )
    # Listing orientation: rz = p[5] - ac while the position turns by +ac.
    result.append(
        _check(
            "source_listing_orientation_sign",
            "Rz(phi) Rz(a) = Rz(a - phi)   (listing's rz = p[5] - ac)",
            "refuted",
            rotz3(phi) * rotz3(a) - rotz3(a - phi),
        )
    )
    result.extend(frame_identities())

    for kind in kinds().values():  # each kind's own identities (its package's derivation)
        result.extend(kind.identities(_check))
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
def frame_identities() -> list[Identity]:
    measured, measured_gamma = frame_residual()
    at_measurement = {res_x: measured[0], res_y: measured[1], gamma: measured_gamma}
    d_true = sp.Matrix([dx_true, dy_true])
    out = []
    new_d, new_alpha = frame_update(+1)
    out.append(
        _check(
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
        _check(
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
        _check(
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


# --- export for the printers -----------------------------------------------------------------


def exported_expressions(derivation: Derivation | None = None) -> dict[str, sp.Expr]:
    """Closed forms the controllers evaluate; inputs tx, ty, tnx, tny, Px, Py and phi."""
    d = derivation or derive()
    trig = [sp.cos(phi), sp.sin(phi)]
    # Grouped by cos/sin so that (P - t) is formed first: less cancellation in float32.
    return {
        "frame_cos": d.D[0, 0],
        "frame_sin": d.D[1, 0],
        "frame_x": sp.collect(sp.expand(d.D[0, 2]), trig),
        "frame_y": sp.collect(sp.expand(d.D[1, 2]), trig),
        "point_x": sp.collect(sp.expand(d.Pn[0]), trig),
        "point_y": sp.collect(sp.expand(d.Pn[1]), trig),
    }


def cse_blocks(derivation: Derivation | None = None) -> dict[str, dict]:
    """Two blocks with common subexpressions eliminated: D (frame) and Pn (point)."""
    exprs = exported_expressions(derivation)
    new_d, _new_alpha = frame_update(+1)
    exprs["new_dx"], exprs["new_dy"] = new_d[0], new_d[1]
    groups = [
        ("frame", ("frame_cos", "frame_sin", "frame_x", "frame_y")),
        ("point", ("point_x", "point_y")),
        ("refine", ("new_dx", "new_dy")),
    ]

    for kind in kinds().values():  # each kind's own closed forms the controllers evaluate
        for block, outputs in kind.printed_blocks().items():
            exprs.update(outputs)
            groups.append((block, tuple(outputs)))
    blocks = {}
    for block, names in groups:
        temps, reduced = sp.cse(
            [exprs[n] for n in names], symbols=sp.numbered_symbols(f"{block}_t"), optimizations="basic"
        )
        readable = {
            sp.cos(phi): "cos_phi",
            sp.sin(phi): "sin_phi",
            Px - tx: "ax",
            Py - ty: "ay",
            sp.cos(alpha): "cos_alpha",
            sp.sin(alpha): "sin_alpha",
        }
        renames = {tmp: sp.Symbol(readable[expr], real=True) for tmp, expr in temps if expr in readable}
        temps = [(renames.get(tmp, tmp), expr.subs(renames)) for tmp, expr in temps]
        reduced = [expr.subs(renames) for expr in reduced]
        blocks[block] = {"temps": temps, "outputs": dict(zip(names, reduced, strict=True))}
    return blocks


def describe(derivation: Derivation | None = None) -> str:
    d = derivation or derive()
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


# --- cache (read by codegen.derived without sympy) -------------------------------------------


def build_cache() -> dict:
    """Everything later steps need from the derivation, as plain JSON data."""

    d = derive()
    blocks = cse_blocks(d)
    printed = {}
    for dialect, printer in printers().items():
        printed[dialect] = {
            name: {
                "temps": [[str(tmp), printer.doprint(expr)] for tmp, expr in block["temps"]],
                "outputs": {out: printer.doprint(expr) for out, expr in block["outputs"].items()},
            }
            for name, block in blocks.items()
        }
    return {
        "description": describe(d),
        "identities": [
            {"name": i.name, "statement": i.statement, "expected": i.expected, "status": i.status, "detail": i.detail}
            for i in identities(d)
        ],
        "blocks": {
            name: {
                "temps": [[str(tmp), sp.sstr(expr)] for tmp, expr in block["temps"]],
                "outputs": {out: sp.sstr(expr) for out, expr in block["outputs"].items()},
            }
            for name, block in blocks.items()
        },
        "printed": printed,
    }


if __name__ == "__main__":
    text = json.dumps(build_cache(), indent=1, sort_keys=True) + "\n"
    if "--write" in sys.argv:
        CACHE_PATH.write_text(text, encoding="utf-8")
        print(f"wrote {CACHE_PATH}")
    else:
        sys.stdout.write(text)
