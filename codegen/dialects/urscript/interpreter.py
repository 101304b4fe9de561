"""URScript interpreter: float32 numbers, radians, poses in metres with rotation vectors."""

from __future__ import annotations

import math
import re

import numpy as np
from lark import Token, Tree

from codegen.dialects import posemath
from codegen.dialects.core.arm import remember_joint_target
from codegen.dialects.core.compiler import Compiler
from codegen.dialects.core.machine import MoveEvent, Program, halt
from codegen.dialects.core.parsing import parse_with_grammar
from codegen.dialects.core.values import F32, Record, RunError, describe, f32, format_general, show
from codegen.dialects.urscript import circle, conveyor, threads
from codegen.robot import solve

INPUT_REGISTER = re.compile(r"(?:input|output)_(?:integer|float|boolean)_register_(\d+)")
# movej/movel keyword arguments and their defaults (URScript manual, module motion): acceleration a,
# speed v (rad/s^2, rad/s for movej; m/s^2, m/s for movel), blend radius r (m; 0: stop at the pose)
# One controller cycle, sync()'s wait: 500 Hz on the e-Series (URScript manual, sync(); get_steptime()).
STEP_TIME_S = 0.002
DIGITAL_MAX = 7  # standard digital I/O 0..7 of the control box (ur.toml signals)
# The clock's move time is the TCP distance over a TCP speed: movel's v is one (m/s); movej's v is a
# joint speed (rad/s), taken as the speed of a TCP 1 m from the axis (enough to order waits).
MM_PER_M = 1000.0
MOVE_DEFAULTS = {"joint": {"a": 1.4, "v": 1.05, "r": 0.0}, "linear": {"a": 1.2, "v": 0.25, "r": 0.0}}
REGISTER_MAX = 47  # registers 0..23 fieldbus, 24..47 RTDE clients (URScript manual)
BOOLEAN_REGISTER_MAX = 127  # boolean registers 0..63 fieldbus, 64..127 RTDE clients (URScript manual)
STRING_MAX = 1023  # characters of a string result (URScript manual, str_cat; ur.toml string_max)


def parse(text: str, filename: str = "<urscript>", positions: bool = True) -> Tree:
    return parse_with_grammar(__file__, text, filename, positions)


class URPose(Record):
    """p[x, y, z, rx, ry, rz] (m, rad), indexable 0..5."""

    KEYS = ("x", "y", "z", "rx", "ry", "rz")

    def __init__(self, values) -> None:
        super().__init__("pose", zip(self.KEYS, (f32(v) for v in values), strict=True))

    def copy(self) -> URPose:
        return URPose(self.values())


def _num(value, where: str, what: str):
    if type(value) is F32:  # the common case first
        return value
    if isinstance(value, bool) or not isinstance(value, int | float | np.number):
        raise RunError(f"{where}: {what} must be a number, got {describe(value)}")
    return value


def _pose(value, where: str) -> URPose:
    if not isinstance(value, URPose):
        raise RunError(f"{where}: expected a pose p[...], got {describe(value)}")
    return value


def _joints(value, where: str, count: int = 6) -> np.ndarray:
    if not isinstance(value, list) or len(value) != count:
        raise RunError(f"{where}: expected a list of {count} numbers")
    out = np.array([float(_num(v, where, "list element")) for v in value])
    posemath.check_finite(tuple(out), where, "list")
    return out


def _to_text(value) -> str:
    if isinstance(value, str):
        return value
    if isinstance(value, URPose):
        return "p[" + ", ".join(format_general(v) for v in value.values()) + "]"
    if isinstance(value, list):
        return "[" + ", ".join(_to_text(v) for v in value) + "]"
    return format_general(value)


def _unary(fn):
    def call(fr, args, kwargs, where):
        if len(args) != 1:
            raise RunError(f"{where}: expected 1 argument")
        return f32(fn(float(_num(args[0], where, "argument"))))

    return call


class URScriptCompiler(threads.ThreadStatements, Compiler):
    name = "urscript"
    index_base = 0

    def __init__(self, filename: str) -> None:
        super().__init__(filename)
        self.threads: dict = {}  # thread definitions by name (codegen/dialects/urscript/threads.py)
        self.thread_runs: list[tuple[str, object]] = []  # (name, node) of each `run name()`, checked by load()

    def make_builtins(self) -> dict:
        def pose_trans(fr, args, kwargs, where):
            a, b = (_pose(v, where) for v in args)
            return URPose(posemath.ur_concat(tuple(a.values()), tuple(b.values())))

        def pose_inv(fr, args, kwargs, where):
            from codegen.poses import invert

            m = posemath.matrix_from_ur_cached(_pose(args[0], where).values())
            return URPose(posemath.ur_from_matrix(invert(m)))

        def pose_add(fr, args, kwargs, where):
            # Not a rigid transform: positions add, rotations compose in the base frame.
            a, b = (_pose(v, where) for v in args)
            ma, mb = posemath.matrix_from_ur_cached(a.values()), posemath.matrix_from_ur_cached(b.values())
            out = np.eye(4)
            out[:3, :3] = mb[:3, :3] @ ma[:3, :3]
            out[:3, 3] = ma[:3, 3] + mb[:3, 3]
            return URPose(posemath.ur_from_matrix(out))

        def move(kind):
            def run(fr, args, kwargs, where):
                if not args:
                    raise RunError(f"{where}: move{kind[0]} needs a target")
                if threads.current(fr) is not None:
                    raise RunError(f"{where}: move{kind[0]} from a thread: not modelled here (the main program moves)")
                target = args[0]
                line = int(where.split(":")[1])
                settings = {key: float(kwargs.get(key, default)) for key, default in MOVE_DEFAULTS[kind].items()}
                settings["load"] = fr.m.extra.get("payload")
                if isinstance(target, list):  # joint positions (rad): no solution to choose
                    if kind != "joint":
                        raise RunError(f"{where}: movel takes a pose")
                    event = MoveEvent(kind, None, line, settings)
                    conveyor.tracked_move(fr, event, 0.0, where)  # refused while tracking
                    fr.m.arm.to_joints(event, np.degrees(_joints(target, where)), where)
                    fr.m.move(event, settings["v"] * MM_PER_M)
                    return
                pose = _pose(target, where)
                posemath.check_finite(pose.values(), where, "move target")
                event = MoveEvent(kind, posemath.matrix_from_ur(pose.values()), line, settings)
                seconds = conveyor.tracked_move(fr, event, settings["v"] * MM_PER_M, where)  # None: not tracking
                # movej to a pose: the solution nearest the current joints; movel keeps the configuration
                fr.m.arm.to_pose(event, where, "nearest" if kind == "joint" else "keep")
                fr.m.move(event, settings["v"] * MM_PER_M, seconds=seconds)  # movej, movel return on arrival

            return run

        def set_tcp(fr, args, kwargs, where):
            # the TCP in the flange frame (m, rotation vector rad): the active tool from here on
            pose = _pose(args[0] if args else kwargs.get("pose"), where)
            posemath.check_finite(pose.values(), where, "tcp")
            fr.m.arm.tcp2flange = posemath.matrix_from_ur(pose.values())

        def set_target_payload(fr, args, kwargs, where):
            # set_target_payload(m, cog, inertia, transition_time): kg, m (URScript manual)
            if len(args) < 2:
                raise RunError(f"{where}: set_target_payload needs a mass and a centre of gravity")
            mass = float(_num(args[0], where, "mass"))
            cog = [1000.0 * float(_num(v, where, "centre of gravity")) for v in _joints(args[1], where, 3)]
            if not mass >= 0:
                raise RunError(f"{where}: payload mass {mass} kg")
            fr.m.extra["payload"] = (mass, *cog)

        def get_inverse_kin(fr, args, kwargs, where):
            # the solution nearest qnear (rad), a runtime exception when there is none (URScript manual)
            pose = _pose(args[0] if args else kwargs.get("x"), where)
            posemath.check_finite(pose.values(), where, "get_inverse_kin pose")
            qnear = kwargs.get("qnear", args[1] if len(args) > 1 else None)
            arm = fr.m.arm
            if arm.arm is None:
                raise RunError(f"{where}: get_inverse_kin needs the arm's kinematics (name the arm: --robot)")
            near = np.degrees(_joints(qnear, where)) if qnear is not None else arm.current(where)
            if near is None:
                raise RunError(f"{where}: get_inverse_kin without qnear before the arm's joints are known")
            tcp2base = posemath.matrix_from_ur(pose.values())
            solutions = solve.branches(arm.arm, solve.flange_poses(tcp2base, arm.tcp2flange))
            q, branch = solve.nearest(arm.arm, solutions, near)
            if np.isnan(q).any():
                raise RunError(f"{where}: get_inverse_kin: no solution (the pose is out of reach)")
            out = [f32(v) for v in np.radians(q)]
            remember_joint_target(arm.arm, np.degrees(np.array([float(v) for v in out])), branch)  # as movej reads it
            return out

        def textmsg(fr, args, kwargs, where):
            text = "".join(_to_text(a) for a in args)
            fr.m.message(text)

        def register(kind):
            top = BOOLEAN_REGISTER_MAX if kind == "boolean" else REGISTER_MAX

            def read(fr, args, kwargs, where):
                index = int(args[0])
                if not 0 <= index <= top:
                    raise RunError(f"{where}: register {index} out of range 0..{top}")
                key = f"input_{kind}_register_{index}"
                live = fr.m.input_signal(key, None)  # a device's value that changes with time (a counter)
                value = fr.m.inputs.get(key, 0) if live is None else live
                if kind == "boolean":
                    return bool(value)
                return int(value) if kind == "integer" else f32(value)

            return read

        def write_output_integer_register(fr, args, kwargs, where):
            index = int(args[0])
            if not 0 <= index <= REGISTER_MAX:
                raise RunError(f"{where}: register {index} out of range 0..{REGISTER_MAX}")
            fr.m.outputs[f"output_integer_register_{index}"] = int(args[1])
            fr.m.output_written(where)

        def read_output_integer_register(fr, args, kwargs, where):
            index = int(args[0])
            if not 0 <= index <= REGISTER_MAX:
                raise RunError(f"{where}: register {index} out of range 0..{REGISTER_MAX}")
            name = f"output_integer_register_{index}"  # what the program wrote, else what it held at the start
            return int(fr.m.outputs.get(name, fr.m.inputs.get(name, 0)))

        def sync(fr, args, kwargs, where):
            # "uses up the remaining 'physical' time a thread has in the current frame" (URScript manual)
            if args or kwargs:
                raise RunError(f"{where}: sync() takes no arguments")
            thread = threads.current(fr)
            if thread is not None:  # a thread: its slice ends here, the next one is the next cycle's
                thread.scheduler.pause(thread)
                return
            watching = fr.m.watching  # the main program: one controller cycle; devices act in between
            fr.m.elapse(STEP_TIME_S if watching is None else watching.cycle, where)

        def sleep(fr, args, kwargs, where):
            if len(args) + len(kwargs) != 1 or (kwargs and "t" not in kwargs):
                raise RunError(f"{where}: sleep(t) takes one argument, the time in s")
            seconds = float(_num(args[0] if args else kwargs["t"], where, "sleep time"))
            if not seconds >= 0 or not math.isfinite(seconds):
                raise RunError(f"{where}: sleep time must be a finite number of seconds >= 0, got {seconds}")
            thread = threads.current(fr)
            if thread is not None:  # a thread: no slices until then (physical time, like sync)
                thread.wake = fr.m.clock + seconds
                thread.scheduler.pause(thread)
                return
            fr.m.elapse(seconds, where)

        def set_standard_digital_out(fr, args, kwargs, where):
            index = int(_num(args[0], where, "digital output"))
            if not 0 <= index <= DIGITAL_MAX or not isinstance(args[1], bool):
                raise RunError(f"{where}: set_standard_digital_out(n, b) takes n 0..{DIGITAL_MAX} and True or False")
            fr.m.set_output(f"standard_digital_out[{index}]", args[1], where)

        def get_standard_digital_in(fr, args, kwargs, where):
            # n: "an integer in [0:7]", returns a bool (URScript manual, e-Series 17.12): the input as the
            # controller reads it now (Machine.input_signal: at this cycle where a device switches it with the
            # tool's pose while the arm moves; in a thread's slice, that slice's cycle)
            if len(args) + len(kwargs) != 1 or (kwargs and "n" not in kwargs):
                raise RunError(f"{where}: get_standard_digital_in(n) takes one argument, the input's number")
            index = args[0] if args else kwargs["n"]
            if type(index) is not int or not 0 <= index <= DIGITAL_MAX:
                raise RunError(f"{where}: get_standard_digital_in(n) takes an integer 0..{DIGITAL_MAX}, got {show(index)}")
            return bool(fr.m.input_signal(f"standard_digital_in[{index}]", False))

        def get_actual_tcp_pose(fr, args, kwargs, where):
            # the TCP in the base frame (m, rotation vector) "based on the actual robot encoder readings"
            # (URScript manual, e-Series 15.6): where the arm is at the clock (on a move's path at a thread's
            # cycle), with the TCP active now
            if args or kwargs:
                raise RunError(f"{where}: get_actual_tcp_pose() takes no arguments")
            machine = fr.m
            machine.arm.resolve()
            pose, tcp2flange = (None, None) if machine.watching is None else machine.watching.pose_at(machine.clock)
            # the flange there, with the TCP active now
            pose = machine.pose_now() if pose is None else pose @ np.linalg.inv(tcp2flange) @ machine.arm.tcp2flange
            if pose is None:
                raise RunError(f"{where}: get_actual_tcp_pose: the arm's pose is not known here (no move to a pose)")
            return URPose(posemath.ur_from_matrix(pose))

        def get_actual_joint_positions(fr, args, kwargs, where):
            return [f32(v) for v in np.radians(fr.m.arm.actual(where))]

        def is_steady(fr, args, kwargs, where):
            return not fr.m.moving  # moves return when the arm has arrived: at rest after every move

        def popup(fr, args, kwargs, where):
            # the operator's dialog; a blocking one waits for the operator, who confirms at once here
            text = _to_text(args[0])
            if len(text) > STRING_MAX:
                raise RunError(f"{where}: popup text longer than {STRING_MAX} characters")
            fr.m.message(text)

        def atan2(fr, args, kwargs, where):
            return f32(math.atan2(float(args[0]), float(args[1])))

        def norm(fr, args, kwargs, where):
            value = args[0]
            if isinstance(value, URPose):
                return f32(math.sqrt(sum(float(v) ** 2 for v in list(value.values())[:3])))
            if isinstance(value, list):
                return f32(math.sqrt(sum(float(v) ** 2 for v in value)))
            return abs(_num(value, where, "norm argument"))

        def pose_tolist(fr, args, kwargs, where):
            return list(_pose(args[0], where).values())

        def to_str(fr, args, kwargs, where):
            return _to_text(args[0])

        def str_cat(fr, args, kwargs, where):
            text = _to_text(args[0]) + _to_text(args[1])
            if len(text) > STRING_MAX:
                raise RunError(f"{where}: str_cat result longer than {STRING_MAX} characters")
            return text

        return {
            "pose_trans": pose_trans,
            "pose_inv": pose_inv,
            "pose_add": pose_add,
            "movej": move("joint"),
            "movel": move("linear"),
            "set_tcp": set_tcp,
            "set_target_payload": set_target_payload,
            "get_inverse_kin": get_inverse_kin,
            "textmsg": textmsg,
            "halt": halt,
            "read_input_integer_register": register("integer"),
            "read_input_float_register": register("float"),
            "read_input_boolean_register": register("boolean"),
            **conveyor.builtins(_pose, _num),
            "write_output_integer_register": write_output_integer_register,
            "read_output_integer_register": read_output_integer_register,
            "sync": sync,
            "sleep": sleep,
            "is_steady": is_steady,
            "get_actual_joint_positions": get_actual_joint_positions,
            "set_standard_digital_out": set_standard_digital_out,
            "get_standard_digital_in": get_standard_digital_in,
            "get_actual_tcp_pose": get_actual_tcp_pose,
            "movec": circle.builtin(_pose, _num, threads.current),
            "popup": popup,
            "sin": _unary(math.sin),
            "cos": _unary(math.cos),
            "tan": _unary(math.tan),
            "sqrt": _unary(math.sqrt),
            "d2r": _unary(math.radians),
            "r2d": _unary(math.degrees),
            "atan2": atan2,
            "norm": norm,
            "floor": _unary(math.floor),
            "pose_to_list": pose_tolist,
            "to_str": to_str,
            "str_cat": str_cat,
        }

    # --- registers by name, for devices: input_* and output_* are the controller's registers ------
    def accepts_input(self, name: str, globals_: dict) -> bool:
        """Input registers (input_integer_register_24, ...) are read by index at run time."""
        match = INPUT_REGISTER.fullmatch(name)
        return (match is not None and int(match.group(1)) <= REGISTER_MAX) or super().accepts_input(name, globals_)

    def device_read(self, machine, name: str):
        if name.startswith("input_"):
            return machine.inputs.get(name, 0)
        if name.startswith("output_"):  # what the program wrote, else what the register held at the start
            return machine.outputs.get(name, machine.inputs.get(name, 0))
        return super().device_read(machine, name)

    def device_write(self, machine, name: str, value) -> bool:
        if name.startswith("input_"):
            machine.inputs[name] = value
            return True
        return super().device_write(machine, name, value)

    # --- rules beyond the common ones ---------------------------------------------------------
    def e_pose_lit(self, node):
        parts = [self.expr(c) for c in node.children[1:]]
        where = self.where(node)
        if len(parts) != 6:
            self.fail(node, f"a pose has 6 numbers, got {len(parts)}")

        def make(fr):
            return URPose([_num(p(fr), where, "pose component") for p in parts])

        return make

    def e_list_lit(self, node):
        parts = [self.expr(c) for c in node.children if c is not None]
        return lambda fr: [p(fr) for p in parts]

    def e_call(self, node):
        callee, args_node = node.children
        if not (isinstance(callee, Tree) and callee.data == "var"):
            self.fail(node, "only named functions can be called")
        name = str(callee.children[0])
        positional, named = [], {}
        for arg in args_node.children if args_node is not None else []:
            if isinstance(arg, Tree) and arg.data == "kwarg":
                named[str(arg.children[0])] = self.src(arg.children[1])
            else:
                positional.append(self.src(arg))
        return self.call_source(name, positional, named, None, self.where(node))

    def s_global_stmt(self, node):
        key, value = str(node.children[0]), self.expr(node.children[1])

        def run(fr):
            fr.m.globals[key] = value(fr)

        return run

    def s_local_stmt(self, node):
        key, value = str(node.children[0]), self.expr(node.children[1])

        def run(fr):
            fr.vars[key] = value(fr)

        return run

    def s_funcdef(self, node):
        name_token, params_node, body = node.children
        if str(name_token) in self.threads:
            self.fail(name_token, f"{name_token} is defined as a thread already")
        params = [(str(p), "IN", None) for p in (params_node.children if params_node is not None else [])]
        self.define_routine(str(name_token), name_token, params, None, node, body.children, unique=False)
        return lambda fr: None  # defined at compile time


def _is_constant(node) -> bool:
    """Literals only (numbers, strings, lists, pose literals): safe to evaluate once."""
    if isinstance(node, Token):
        return node.type in ("NUMBER", "STRING", "POSE_OPEN")
    if node.data in ("call", "var"):
        return False
    return all(_is_constant(c) for c in node.children if c is not None)


def load(text: str, filename: str = "<urscript>") -> Program:
    """Parse and compile; the outermost `def` is the program, its variables are the globals.

    Its leading constant assignments and function definitions run once; the rest on every run.
    """
    tree = parse(text, filename)
    compiler = URScriptCompiler(filename)
    top = [c for c in tree.children if isinstance(c, Tree)]
    programs = [c for c in top if c.data == "funcdef"]
    if len(top) == 1 and len(programs) == 1:
        statements = [c for c in programs[0].children[2].children if isinstance(c, Tree)]
        name = str(programs[0].children[0])
    else:
        statements, name = top, filename
    split = 0
    while split < len(statements) and (
        statements[split].data in ("funcdef", "threaddef")
        or (statements[split].data == "assign" and _is_constant(statements[split].children[1]))
    ):
        split += 1
    prefix_statements = []
    for statement in statements[:split]:
        prefix_statements.append(compiler.stmt(statement))

    def prefix(fr):
        for statement in prefix_statements:
            statement(fr)

    rest = compiler.block(statements[split:])
    compiler.check_thread_runs()
    return Program(name, compiler, prefix, None, threads.ending_threads(rest))
