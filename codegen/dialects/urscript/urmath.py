"""URScript's math, pose math, lists, strings and struct built-ins (the manual's module urmath and string functions)."""

# The URScript Programming Language, e-Series (SW 5.x, the HTML script manual at universal-robots.com, module
# urmath), as each function's page states it:
# - pose_trans(p_from, p_from_to): T_world->to = T_world->from * T_from->to (a matrix product).
# - pose_inv(p_from): the inverse transformation.
# - pose_add(p_1, p_2): "p_3.P = p_1.P + p_2.P, p_3.R = p_1.R * p_2.R" (positions add, rotation matrices
#   multiply, R_1 first; not a rigid transform). pose_sub(p_to, p_from): the manual states no formula; UR's
#   staff on the UR forum ("Doubts on pose_sub usage and meaning"): made so that pose_add(pose_sub(p_1, p_2),
#   p_2) == p_1, hence P = p_to.P - p_from.P, R = p_to.R * p_from.R^T (modelled so).
# - interpolate_pose(p_from, p_to, alpha): "a pose going in a straight line (and geodetic orientation change)
#   from p_from to p_to"; alpha 0 gives p_from, 1 gives p_to, outside [0, 1] a pose before or after them on
#   that line: position p_from + alpha (p_to - p_from), rotation R_from exp(alpha log(R_from^T R_to)).
# - point_dist(p_from, p_to): the distance between the positions. pose_dist: the manual gives no formula
#   (UR's staff: "more like time ... than actual distance"): not modelled, refused by name.
# - rpy2rotvec / rotvec2rpy: "Rrpy = Rz(yaw) Ry(pitch) Rx(roll)" (extrinsic X-Y-Z), radians.
# - norm(a): a number's absolute value, a list's or a pose's euclidean norm (a pose's: its position's);
#   normalize(v): v / norm(v) for a list of numbers.
# - d2r, r2d, sin, cos, tan, asin, acos, atan, atan2, sqrt, pow, log(b, f) (logarithm of f to the base b),
#   floor, ceil: float results, stored as float32 (numbers are 32-bit, Numbers, Variables and Types).
# - get_list_length(v), length(v) (a list's or a string's), str_cat, str_len, to_str, to_num, str_empty.
# - struct(name=value, ...) (Numbers, Variables and Types, e-Series: not confirmed in the manual text at
#   hand; modelled as named values read and changed by name).

from __future__ import annotations

import math

import numpy as np

from codegen.dialects import posemath
from codegen.dialects.core.values import RunError, describe, f32
from codegen.dialects.urscript.values import (
    INT_BITS,
    Struct,
    URPose,
    arguments,
    finite,
    int32,
    joints,
    matrix,
    num,
    pose,
    to_text,
    unary,
    vector,
)
from codegen.poses import invert, rotmat_from_rotvec, rotvec_from_rotmat

STRING_MAX = 1023  # characters of a string result (URScript manual, str_cat; ur.toml string_max)


def _rotation(rx, ry, rz) -> np.ndarray:
    return rotmat_from_rotvec([float(rx), float(ry), float(rz)])


def rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """Rz(yaw) Ry(pitch) Rx(roll) (URScript manual, rpy2rotvec)."""
    cr, sr, cp, sp, cy, sy = (
        math.cos(roll),
        math.sin(roll),
        math.cos(pitch),
        math.sin(pitch),
        math.cos(yaw),
        math.sin(yaw),
    )
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def rpy_of(r: np.ndarray) -> tuple[float, float, float]:
    """(roll, pitch, yaw) of a rotation matrix, pitch in [-pi/2, pi/2]."""
    pitch = math.atan2(-r[2, 0], math.hypot(r[0, 0], r[1, 0]))
    if math.hypot(r[0, 0], r[1, 0]) < 1e-12:  # gimbal lock: yaw 0, the roll takes the whole turn
        return math.atan2(-r[1, 2], r[1, 1]), pitch, 0.0
    return math.atan2(r[2, 1], r[2, 2]), pitch, math.atan2(r[1, 0], r[0, 0])


def _pose_of(m: np.ndarray) -> URPose:
    return URPose(posemath.ur_from_matrix(m))


def builtins() -> dict:
    def pose_trans(fr, args, kwargs, where):
        if len(args) == 2 and not kwargs:
            first, second = args
        else:
            a = arguments("pose_trans", ("p_from", "p_from_to"), {}, args, kwargs, where)
            first, second = a["p_from"], a["p_from_to"]
        if type(first) is not URPose or type(second) is not URPose:
            first, second = pose(first, where, "p_from"), pose(second, where, "p_from_to")
        return URPose(posemath.ur_concat(tuple(first.values()), tuple(second.values())))

    def pose_inv(fr, args, kwargs, where):
        a = arguments("pose_inv", ("p_from",), {}, args, kwargs, where)
        return _pose_of(invert(posemath.matrix_from_ur_cached(pose(a["p_from"], where, "p_from").values())))

    def pose_add(fr, args, kwargs, where):
        a = arguments("pose_add", ("p_1", "p_2"), {}, args, kwargs, where)
        m1, m2 = matrix(a["p_1"], where, "p_1"), matrix(a["p_2"], where, "p_2")
        out = np.eye(4)
        out[:3, :3] = m1[:3, :3] @ m2[:3, :3]
        out[:3, 3] = m1[:3, 3] + m2[:3, 3]
        return _pose_of(out)

    def pose_sub(fr, args, kwargs, where):
        a = arguments("pose_sub", ("p_to", "p_from"), {}, args, kwargs, where)
        to, start = matrix(a["p_to"], where, "p_to"), matrix(a["p_from"], where, "p_from")
        out = np.eye(4)
        out[:3, :3] = to[:3, :3] @ start[:3, :3].T
        out[:3, 3] = to[:3, 3] - start[:3, 3]
        return _pose_of(out)

    def interpolate_pose(fr, args, kwargs, where):
        a = arguments("interpolate_pose", ("p_from", "p_to", "alpha"), {}, args, kwargs, where)
        start, end = matrix(a["p_from"], where, "p_from"), matrix(a["p_to"], where, "p_to")
        alpha = finite(float(num(a["alpha"], where, "alpha")), where, "alpha")
        turn = rotvec_from_rotmat(start[:3, :3].T @ end[:3, :3])
        out = np.eye(4)
        out[:3, :3] = start[:3, :3] @ rotmat_from_rotvec(alpha * np.asarray(turn, dtype=float))
        out[:3, 3] = start[:3, 3] + alpha * (end[:3, 3] - start[:3, 3])
        return _pose_of(out)

    def point_dist(fr, args, kwargs, where):
        a = arguments("point_dist", ("p_from", "p_to"), {}, args, kwargs, where)
        start, end = matrix(a["p_from"], where, "p_from"), matrix(a["p_to"], where, "p_to")
        return f32(float(np.linalg.norm(end[:3, 3] - start[:3, 3])) / 1000.0)

    def rpy2rotvec(fr, args, kwargs, where):
        a = arguments("rpy2rotvec", ("rpy_vector",), {}, args, kwargs, where)
        roll, pitch, yaw = vector(a["rpy_vector"], where, "rpy_vector")
        return [f32(v) for v in rotvec_from_rotmat(rpy_matrix(roll, pitch, yaw))]

    def rotvec2rpy(fr, args, kwargs, where):
        a = arguments("rotvec2rpy", ("rotation_vector",), {}, args, kwargs, where)
        return [f32(v) for v in rpy_of(_rotation(*vector(a["rotation_vector"], where, "rotation_vector")))]

    def norm(fr, args, kwargs, where):
        value = args[0] if len(args) == 1 and not kwargs else arguments("norm", ("a",), {}, args, kwargs, where)["a"]
        if isinstance(value, URPose):
            return f32(math.sqrt(sum(float(v) ** 2 for v in list(value.values())[:3])))
        if isinstance(value, list):
            return f32(math.sqrt(sum(float(num(v, where, "norm element")) ** 2 for v in value)))
        return abs(num(value, where, "norm argument"))

    def normalize(fr, args, kwargs, where):
        a = arguments("normalize", ("v",), {}, args, kwargs, where)
        if not isinstance(a["v"], list) or not a["v"]:
            raise RunError(f"{where}: normalize takes a list of numbers, got {describe(a['v'])}")
        values = [float(num(v, where, "normalize element")) for v in a["v"]]
        length = math.sqrt(sum(v * v for v in values))
        if length == 0:
            raise RunError(f"{where}: normalize of a vector of length 0")
        return [f32(v / length) for v in values]

    def atan2(fr, args, kwargs, where):
        a = arguments("atan2", ("y", "x"), {}, args, kwargs, where)
        return f32(math.atan2(float(num(a["y"], where, "y")), float(num(a["x"], where, "x"))))

    def power(fr, args, kwargs, where):
        a = arguments("pow", ("base", "exponent"), {}, args, kwargs, where)
        try:
            return f32(math.pow(float(num(a["base"], where, "base")), float(num(a["exponent"], where, "exponent"))))
        except (ValueError, OverflowError):
            raise RunError(f"{where}: pow({a['base']}, {a['exponent']}) has no real value here") from None

    def log(fr, args, kwargs, where):
        a = arguments("log", ("b", "f"), {}, args, kwargs, where)
        try:
            return f32(math.log(float(num(a["f"], where, "f")), float(num(a["b"], where, "b"))))
        except (ValueError, ZeroDivisionError):
            raise RunError(f"{where}: log of {a['f']} to the base {a['b']} is not defined") from None

    def length(fr, args, kwargs, where):
        a = arguments("length", ("v",), {}, args, kwargs, where)
        if not isinstance(a["v"], list | str):
            raise RunError(f"{where}: length of {describe(a['v'])}: a list or a string has one")
        return len(a["v"])

    def to_str(fr, args, kwargs, where):
        return to_text(arguments("to_str", ("val",), {}, args, kwargs, where)["val"])

    def to_num(fr, args, kwargs, where):
        text = arguments("to_num", ("str",), {}, args, kwargs, where)["str"]
        if not isinstance(text, str):
            raise RunError(f"{where}: to_num takes a string, got {describe(text)}")
        try:
            if text.strip().lstrip("+-").isdigit():
                return int32(int(text), "to_num", where)
            return finite(f32(float(text)), where, "to_num")
        except ValueError:
            raise RunError(f"{where}: to_num: {text!r} is not a number") from None

    def str_cat(fr, args, kwargs, where):
        a = arguments("str_cat", ("op1", "op2"), {}, args, kwargs, where)
        text = to_text(a["op1"]) + to_text(a["op2"])
        if len(text) > STRING_MAX:
            raise RunError(f"{where}: str_cat result longer than {STRING_MAX} characters")
        return text

    def str_len(fr, args, kwargs, where):
        text = arguments("str_len", ("str",), {}, args, kwargs, where)["str"]
        if not isinstance(text, str):
            raise RunError(f"{where}: str_len takes a string, got {describe(text)}")
        return len(text)

    def str_empty(fr, args, kwargs, where):
        text = arguments("str_empty", ("str",), {}, args, kwargs, where)["str"]
        return isinstance(text, str) and not text

    def pose_to_list(fr, args, kwargs, where):
        return list(pose(arguments("pose_to_list", ("p",), {}, args, kwargs, where)["p"], where).values())

    def binary_list_to_integer(fr, args, kwargs, where):
        # the list's booleans as the bits of an integer, the first the least significant (URScript manual)
        bits = arguments("binary_list_to_integer", ("l",), {}, args, kwargs, where)["l"]
        if not isinstance(bits, list) or not bits or any(not isinstance(b, bool) for b in bits):
            raise RunError(f"{where}: binary_list_to_integer takes a list of booleans, got {describe(bits)}")
        if len(bits) > INT_BITS:
            raise RunError(f"{where}: binary_list_to_integer: {len(bits)} bits, at most {INT_BITS}")
        return int32(sum(1 << i for i, bit in enumerate(bits) if bit), "binary_list_to_integer", where)

    def wrench_trans(fr, args, kwargs, where):
        # the wrench [F (N), M (Nm)] seen from the frame T_from_to (its pose in the wrench's frame, m): force and
        # torque in its axes, the torque about its origin: R^T F, R^T (M - p x F) (assumed: the manual says "move
        # point of view of a wrench" and prints no formula; the pose read as pose_trans reads its second pose)
        a = arguments("wrench_trans", ("T_from_to", "w"), {}, args, kwargs, where)
        to = matrix(a["T_from_to"], where, "T_from_to")
        wrench = joints(a["w"], where, 6, "wrench_trans w")
        rot, offset_m = to[:3, :3], to[:3, 3] / 1000.0
        force, torque = wrench[:3], wrench[3:]
        out = np.concatenate((rot.T @ force, rot.T @ (torque - np.cross(offset_m, force))))
        return [f32(v) for v in out]

    def random(fr, args, kwargs, where):
        # a number in [0, 1) (URScript manual); drawn from a generator seeded alike at each run's start, so that
        # a run repeats (the controller's numbers differ run to run: assumed uniform)
        arguments("random", (), {}, args, kwargs, where)
        return f32(fr.m.state.random().random())

    def struct(fr, args, kwargs, where):
        if args:
            raise RunError(f"{where}: struct takes named values only: struct(name=value, ...)")
        return Struct(kwargs)

    return {
        "pose_trans": pose_trans,
        "pose_inv": pose_inv,
        "pose_add": pose_add,
        "pose_sub": pose_sub,
        "interpolate_pose": interpolate_pose,
        "point_dist": point_dist,
        "rpy2rotvec": rpy2rotvec,
        "rotvec2rpy": rotvec2rpy,
        "norm": norm,
        "normalize": normalize,
        "sin": unary(math.sin),
        "cos": unary(math.cos),
        "tan": unary(math.tan),
        "asin": unary(math.asin),
        "acos": unary(math.acos),
        "atan": unary(math.atan),
        "sqrt": unary(math.sqrt),
        "d2r": unary(math.radians),
        "r2d": unary(math.degrees),
        "floor": unary(math.floor),
        "ceil": unary(math.ceil),
        "atan2": atan2,
        "pow": power,
        "log": log,
        "length": length,
        "get_list_length": length,
        "to_str": to_str,
        "to_num": to_num,
        "str_cat": str_cat,
        "str_len": str_len,
        "str_empty": str_empty,
        "pose_to_list": pose_to_list,
        "struct": struct,
        "binary_list_to_integer": binary_list_to_integer,
        "wrench_trans": wrench_trans,
        "random": random,
    }
