"""Palletizing's math in sympy (source 004): the pallet frame from three points and the box pose, proven.

The identities are proven with the check codegen/derivation.py passes in (check(name, statement,
expected, residual[, fixed]) -> Identity): this module does not import it, it is imported by it."""

from __future__ import annotations

from functools import cache

import sympy as sp

from codegen import protocol
from codegen.symrot import rotx3, roty3, rotz3

# Palletizing (source 004): the pallet frame from three taught points, O on the pallet, PX on its +x, PY on
# the +y side; u = PX - O, v = PY - O (docs/kinds/pallet.md).
ux, uy, uz, vx, vy, vz = sp.symbols("ux uy uz vx vy vz", real=True)
u_pallet, v_pallet = sp.Matrix([ux, uy, uz]), sp.Matrix([vx, vy, vz])


def pallet_frame(u: sp.Matrix, v: sp.Matrix) -> sp.Matrix:
    """x along u, z = x cross v normalised, y = z cross x: the rotation pallet2base."""
    x = u / u.norm()
    z = x.cross(v)
    z = z / z.norm()
    return sp.Matrix.hstack(x, z.cross(x), z)


def source_pallet_frame(u: sp.Matrix, v: sp.Matrix) -> sp.Matrix:
    """Source 004 eq. 1: n = u/|u|, m = v/|v| taken as the y axis itself, a = n cross m."""
    n, m = u / u.norm(), v / v.norm()
    return sp.Matrix.hstack(n, m, n.cross(m))


@cache  # independent of the derivation: proved once per process
def pallet_identities(check) -> list:
    five = sp.pi / 36  # PY taught 5 deg off square: v turned 5 deg from the true y axis
    off_square = {ux: 104, uy: 0, uz: 0, vx: 78 * sp.sin(five), vy: 78 * sp.cos(five), vz: 0}
    frame, source = pallet_frame(u_pallet, v_pallet), source_pallet_frame(u_pallet, v_pallet)
    return [
        check(
            "pallet_frame_orthonormal",
            "x = u/|u|, z = x cross v/|.|, y = z cross x: R^T R = I for any PX, PY off the x line",
            "holds",
            frame.T * frame - sp.eye(3),
        ),
        check(
            "source_pallet_frame",
            "source 004 eq. 1 (m = (PY - O)/|.| as the y axis): R^T R = I; with PY 5 deg off square",
            "refuted",
            source.T * source - sp.eye(3),
            fixed=off_square,
        ),
    ]


@cache  # independent of the derivation: proved once per process
def box_pose_identities(check) -> list:
    """The forms the pallet programs compute a box's pose in (codegen/kinds/pallet/, templates/<t>/kinds/pallet.*):
    target = F . Trans(x, y, z) . Rz(angle) . Rz(a0) Ry(b0) Rx(c0), F the pallet frame."""
    x, y, z, dz, angle, a0, b0, c0, gamma = sp.symbols("box_x box_y box_z box_dz box_angle a0 b0 c0 gamma", real=True)
    ox, oy, oz = sp.symbols("pallet_ox pallet_oy pallet_oz", real=True)
    tool = rotz3(a0) * roty3(b0) * rotx3(c0)
    box = sp.Matrix([x, y, z])
    level = rotz3(gamma)  # a level pallet: its frame turns about the base's z only
    printed = level_box_position()  # the dtrans program's position, printed from these expressions
    names = {"PAL_OX": ox, "PAL_OY": oy, "PAL_COS": sp.cos(gamma), "PAL_SIN": sp.sin(gamma), "x": x, "y": y}
    program = {sp.Symbol(k, real=True): v for k, v in names.items()}
    dtrans_position = sp.Matrix([*(e.subs(program) for e in printed), oz + z])
    return [
        check(
            "box_orientation_one_turn",
            "Rz(angle) Rz(a0) Ry(b0) Rx(c0) = Rz(angle + a0) Ry(b0) Rx(c0)   (RAPID OrientZYX(angle + a0, b0, c0))",
            "holds",
            rotz3(angle) * tool - rotz3(angle + a0) * roty3(b0) * rotx3(c0),
        ),
        check(
            "box_pose_on_a_level_pallet",
            "F = Trans(o) Rz(gamma): position o + Rz(gamma) (x, y, z), rotation Rz(gamma + angle + a0) Ry(b0) Rx(c0)"
            "   (the dtrans program, which has no pose product)",
            "holds",
            sp.Matrix.vstack(
                level * rotz3(angle) * tool - rotz3(gamma + angle + a0) * roty3(b0) * rotx3(c0),
                (sp.Matrix([ox, oy, oz]) + level * box - dtrans_position).T,
            ),
        ),
        check(
            "box_offset_in_the_pallet_frame",
            "Trans(0, 0, dz) Trans(x, y, z) Rz(angle) T0 = Trans(x, y, z + dz) Rz(angle) T0   (entry, approach and "
            "retreat move along the pallet's axes, not the tool's: an offset frame before the box's, or Offs)",
            "holds",
            box + sp.Matrix([0, 0, dz]) - sp.Matrix([x, y, z + dz]),
        ),
        check(
            "box_offset_along_the_tool",
            "an offset applied after the tool's orientation (Trans(x,y,z) Rz(angle) T0 Trans(0,0,dz)) is the same: "
            "with the tool pointing down it moves the entry below the box",
            "refuted",
            box + rotz3(angle) * tool * sp.Matrix([0, 0, dz]) - sp.Matrix([x, y, z + dz]),
            fixed={c0: sp.pi, b0: 0, a0: 0, dz: sp.Rational(13, 2)},
        ),
    ]


def level_box_position() -> tuple[sp.Expr, sp.Expr]:
    """x, y of a box's place in the base frame on a level pallet, in the program's names: the frame's
    origin PAL_OX, PAL_OY and turn (PAL_COS, PAL_SIN), the box's x, y in the pallet frame (proven equal to
    the pose product by box_pose_on_a_level_pallet)."""
    ox, oy, cos_g, sin_g, x, y = sp.symbols("PAL_OX PAL_OY PAL_COS PAL_SIN x y", real=True)
    return ox + cos_g * x - sin_g * y, oy + sin_g * x + cos_g * y


class DerivationPart(protocol.Derivation):
    """The pallet frame and a box's pose, proved; the level box's position printed for the controllers."""

    def identities(self, check) -> list:
        return [*pallet_identities(check), *box_pose_identities(check)]

    def printed_blocks(self) -> dict:
        box_px, box_py = level_box_position()
        return {"box": {"box_px": box_px, "box_py": box_py}}
