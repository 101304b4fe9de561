"""URScript's motion, tool, payload and kinematics built-ins (the manual's module motion and internals)."""

# The URScript Programming Language, e-Series (SW 5.x, modules motion and internals), as the pages state them:
# - movej(q, a=1.4, v=1.05, t=0, r=0): q joint positions (rad) or a pose (the inverse kinematics nearest the
#   current joints); a, v the leading axis' acceleration and speed (rad/s^2, rad/s); t: "time [s]" of the
#   move (v and a are then ignored); r: blend radius (m). movel(pose, a=1.2, v=0.25, t=0, r=0): linear in tool
#   space, a and v of the tool (m/s^2, m/s). movep(pose, a=1.2, v=0.25, r=0): "Move Process": linear with
#   constant tool speed and circular blends. movec: circle.py.
# - speedl(xd, a, t, aRot='a'): "Accelerate linearly in Cartesian space and continue with constant tool
#   speed. The time t is optional; if provided the function will return after time t, regardless of the
#   target speed has been reached. If the time t is not provided, the function will return when the target
#   speed is reached" (xd: tool speed, m/s and rad/s, base frame). speedj(qd, a, t): the same in joint space.
#   stopl(a, aRot), stopj(a): decelerate to a stop.
# - servoj(q, a, v, t=0.002, lookahead_time=0.1, gain=300): servo to joint positions q; "the function is
#   blocking for time t".
# - set_tcp(pose): the active TCP (flange frame). set_payload(m, cog) (deprecated on the e-Series),
#   set_payload_mass(m), set_payload_cog(cog), set_target_payload(m, cog, inertia, transition_time): the
#   payload (kg, m). get_tcp_offset(): the active TCP. get_target_tcp_pose(): "the current target tool pose";
#   get_actual_tcp_pose(): the TCP from the encoders; get_forward_kin(q, tcp): the TCP pose of joints q;
#   get_inverse_kin(x, qnear, ...): the solution nearest qnear; get_tcp_force(): "the wrench (force/torque
#   vector) at the TCP".
# Modelled so (assumptions where the manual leaves it open): a move takes its t where given, else the TCP's
# distance over v (movej: v as the speed of a TCP 1 m from the axis), accelerations not modelled (recorded);
# speedl / speedj with t move the arm at that speed for t seconds (no ramp); without t the arm moves at that
# speed from the call until the next motion command, stopl / stopj or the program's end, and the trace has
# one move for that travel; a stop is immediate (its deceleration recorded, not modelled); get_tcp_force() is
# the zero wrench: nothing here pushes on the tool (a program that waits for a contact force waits for ever:
# the time limit ends it); a move from a thread is refused. Each move's settings (MoveEvent.settings, keys
# documented in codegen/dialects/urscript/__init__.py) record a, v, r, t, the payload and the TCP set.

from __future__ import annotations

import numpy as np

from codegen.dialects import posemath
from codegen.dialects.core.arm import remember_joint_target
from codegen.dialects.core.machine import MoveEvent
from codegen.dialects.core.ramp import UNKNOWN_TRAVEL_S
from codegen.dialects.core.values import F32, RunError, f32
from codegen.dialects.urscript import conveyor, threads
from codegen.dialects.urscript.values import MM_PER_M, URPose, arguments, joints, matrix, num, pose, vector
from codegen.poses import rotmat_from_rotvec
from codegen.robot import solve
from codegen.world import loads

MOVES = {  # parameters and the manual's defaults
    "movej": (("q", "a", "v", "t", "r"), {"a": 1.4, "v": 1.05, "t": 0.0, "r": 0.0}),
    "movel": (("pose", "a", "v", "t", "r"), {"a": 1.2, "v": 0.25, "t": 0.0, "r": 0.0}),
    "movep": (("pose", "a", "v", "r"), {"a": 1.2, "v": 0.25, "r": 0.0}),
}
KIND = {"movej": "joint", "movel": "linear", "movep": "process"}
KEEPS_INERTIA = ("set_payload_mass", "set_payload_cog")  # the setters of one part of the load: the rest stays
NUMBER = frozenset({F32, float, int})  # a move's numbers that need no check (bool is not int here)


def line_of(where: str) -> int:
    return int(where.split(":")[1]) if where.count(":") >= 2 else 0


def base_settings(fr, name: str, values: dict) -> dict:
    """A move's settings: its numbers, the payload and the TCP the program set (None: not set)."""
    settings = {key: float(value) for key, value in values.items()}
    state = fr.m.state
    settings["load"] = state.payload
    settings["tcp"] = state.tcp
    settings["move"] = name
    return settings


class SpeedMode:
    """speedl / speedj without a time: the arm moves at that speed from `start_time` until it is settled."""

    def __init__(self, name: str, start, velocity: np.ndarray, start_time: float, settings: dict, where: str):
        self.name, self.start, self.velocity, self.start_time = name, start, velocity, start_time
        self.settings, self.where = settings, where

    def pose_at(self, t: float) -> np.ndarray:
        return _travel(self.start, self.velocity, t - self.start_time)


def _travel(start: np.ndarray, xd: np.ndarray, seconds: float) -> np.ndarray:
    """A tool pose moved at the tool speed xd (m/s, rad/s, base frame) for `seconds`."""
    end = np.array(start, dtype=float)
    end[:3, 3] = start[:3, 3] + xd[:3] * MM_PER_M * seconds
    end[:3, :3] = rotmat_from_rotvec(xd[3:] * seconds) @ start[:3, :3]
    return end


def settle(fr, where: str) -> None:
    """The speed motion under way ends now: its travel is one move in the trace (nothing under way: no effect)."""
    machine = fr.m
    mode, machine.state.speed = machine.state.speed, None
    if mode is None:
        return
    seconds = max(0.0, machine.clock - mode.start_time)
    settings = {**mode.settings, "t": seconds}
    if mode.name == "speedl":
        event = MoveEvent("linear", mode.pose_at(machine.clock), line_of(mode.where), settings)
        machine.arm.from_start()
        machine.arm.to_pose(event, mode.where, "keep")
    else:
        event = MoveEvent("joint", None, line_of(mode.where), settings)
        machine.arm.to_joints(event, mode.start + mode.velocity * seconds, mode.where)
    machine.arm_until = machine.clock  # the travel ended at the clock
    machine.move(event, None, seconds=0.0)


def _no_thread(fr, name: str, where: str) -> None:
    if threads.current(fr) is not None:
        raise RunError(f"{where}: {name} from a thread: not modelled here (the main program moves the arm)")


def _tool_pose(fr, where: str, name: str) -> np.ndarray:
    """Where the TCP is now: after the moves so far, else where the arm stands (its joints and kinematics)."""
    machine = fr.m
    pose_now = machine.pose_now()
    if pose_now is None and machine.last_move is not None and machine.arm.arm is not None:
        machine.arm.resolve()  # a move to joints: its pose from the kinematics
        pose_now = machine.last_move.tcp2base
    if pose_now is None and machine.arm.arm is not None and machine.arm.joints is not None:
        pose_now = machine.arm.arm.kin.fk(np.asarray(machine.arm.joints, dtype=float)) @ machine.arm.tcp2flange
    if pose_now is None:
        raise RunError(f"{where}: {name}: the arm's pose is not known here (no move to a pose before it)")
    return pose_now


@loads.Remembered
def _flat_load(mass: float, x: float, y: float, z: float, *tensor: float) -> tuple:
    return tuple(loads.from_tensor(mass, [x, y, z], list(tensor)).flat())


def builtins() -> dict:
    def move(name: str):
        params, defaults = MOVES[name]
        kind = KIND[name]

        numeric = params[1:]
        named = frozenset(numeric)
        timed = "t" in named
        default_a, default_v = defaults["a"], defaults["v"]
        joint_rule = "nearest" if name == "movej" else "keep"  # movej: nearest the joints; movel, movep: keep

        def run(fr, args, kwargs, where):
            machine = fr.m
            state = machine.state
            if state.threads is not None:
                _no_thread(fr, name, where)
            if state.speed is not None:
                settle(fr, where)
            if len(args) == 1 and kwargs.keys() <= named:  # the everyday call: movel(p, a=1.2, v=0.25)
                target, given = args[0], kwargs
            else:
                given = arguments(name, params, defaults, args, kwargs, where)
                target = given[params[0]]
            a, v, r = given.get("a", default_a), given.get("v", default_v), given.get("r", 0.0)
            t = given.get("t", 0.0)
            if not (type(a) in NUMBER and type(v) in NUMBER and type(r) in NUMBER and type(t) in NUMBER):
                a, v, r, t = (num(x, where, f"{name} {k}") for x, k in ((a, "a"), (v, "v"), (r, "r"), (t, "t")))
            a, v, r, t = float(a), float(v), float(r), float(t)
            if not (v > 0 and a > 0 and r >= 0 and t >= 0):
                raise RunError(f"{where}: {name} needs a > 0, v > 0, r >= 0 and t >= 0")
            settings = {"a": a, "v": v, "t": t, "r": r} if timed else {"a": a, "v": v, "r": r}
            settings["load"] = state.payload
            settings["tcp"] = state.tcp
            settings["move"] = name
            line = int(where.rsplit(":", 2)[1])
            if type(target) is list:
                if name != "movej":  # "forward kinematics is used" (movel's page)
                    arm = machine.arm
                    if arm.arm is None:
                        raise RunError(f"{where}: {name} to joint positions needs the arm's kinematics (--robot)")
                    q = np.degrees(joints(target, where, 6, f"{name} q"))
                    target = URPose(posemath.ur_from_matrix(arm.arm.kin.fk(q) @ arm.tcp2flange))
                else:  # joint positions (rad): no solution to choose
                    event = MoveEvent(kind, None, line, settings)
                    conveyor.tracked_move(fr, event, 0.0, where)  # refused while tracking
                    q = np.degrees(joints(target, where, 6, "movej q"))
                    machine.arm.to_joints(event, q, where)
                    if machine.arm.arm is not None:  # the pose the joints put the tool at: the next move starts there
                        event.tcp2base = machine.arm.arm.kin.fk(q) @ machine.arm.tcp2flange
                    # the joint move's own time stays the assumed one (its joint speed's profile is not modelled)
                    machine.move(event, v * MM_PER_M, seconds=t or UNKNOWN_TRAVEL_S)
                    return
            event = MoveEvent(kind, matrix(target, where, f"{name} target"), line, settings)
            tracked = conveyor.tracked_move(fr, event, v * MM_PER_M, where)  # None: not tracking
            arm = machine.arm
            if not arm.known:
                arm.from_start()
            arm.to_pose(event, where, joint_rule)
            machine.move(event, v * MM_PER_M, seconds=(t or None) if tracked is None else tracked)  # on arrival

        return run

    def speed(name: str):
        def run(fr, args, kwargs, where):
            _no_thread(fr, name, where)
            first = "xd" if name == "speedl" else "qd"
            params = (first, "a", "t", "aRot") if name == "speedl" else (first, "a", "t")
            a = arguments(name, params, {"t": 0.0, "aRot": None}, args, kwargs, where)
            velocity = joints(a[first], where, 6, f"{name} {first}")
            seconds = float(num(a["t"], where, f"{name} t"))
            settings = base_settings(fr, name, {"a": num(a["a"], where, f"{name} a"), "t": seconds})
            settings[first] = tuple(float(v) for v in velocity)
            machine = fr.m
            settle(fr, where)
            if name == "speedl":
                start = _tool_pose(fr, where, name)
                settings["v"] = float(np.linalg.norm(velocity[:3]))
            else:
                start = machine.arm.current(where)
                if start is None:
                    raise RunError(f"{where}: speedj: the arm's joints are not known here (codegen run: --start)")
                velocity = np.degrees(velocity)
            if seconds <= 0:  # until the next motion command or a stop
                machine.state.speed = SpeedMode(name, start, velocity, machine.clock, settings, where)
                return
            if name == "speedl":
                event = MoveEvent("linear", _travel(start, velocity, seconds), line_of(where), settings)
                machine.arm.from_start()
                machine.arm.to_pose(event, where, "keep")
            else:
                event = MoveEvent("joint", None, line_of(where), settings)
                machine.arm.to_joints(event, start + velocity * seconds, where)
            machine.move(event, None, seconds=seconds)

        return run

    def stop(name: str):
        def run(fr, args, kwargs, where):
            params = ("a", "aRot") if name == "stopl" else ("a",)
            a = arguments(name, params, {"aRot": None}, args, kwargs, where)
            num(a["a"], where, f"{name} a")
            settle(fr, where)
            fr.m.arrive(where)

        return run

    def servoj(fr, args, kwargs, where):
        _no_thread(fr, "servoj", where)
        params = ("q", "a", "v", "t", "lookahead_time", "gain")
        defaults = {"a": 0.0, "v": 0.0, "t": 0.002, "lookahead_time": 0.1, "gain": 300}
        a = arguments("servoj", params, defaults, args, kwargs, where)
        settle(fr, where)
        settings = base_settings(fr, "servoj", {k: num(a[k], where, f"servoj {k}") for k in params[1:]})
        seconds = settings["t"]
        if not seconds > 0:
            raise RunError(f"{where}: servoj needs t > 0")
        event = MoveEvent("joint", None, line_of(where), settings)
        fr.m.arm.to_joints(event, np.degrees(joints(a["q"], where, 6, "servoj q")), where)
        fr.m.move(event, None, seconds=seconds)

    def set_tcp(fr, args, kwargs, where):
        # the TCP in the flange frame (m, rotation vector rad): the active tool from here on
        a = arguments("set_tcp", ("pose", "tcp_name"), {"tcp_name": ""}, args, kwargs, where)
        fr.m.arm.tcp2flange = matrix(a["pose"], where, "tcp")
        fr.m.state.tcp = tuple(float(v) for v in pose(a["pose"], where).values())

    def _payload(fr, mass, cog, where: str, name: str, inertia=None) -> None:
        # the load as verify compares it (codegen.world.loads.Load.flat): mass kg, cog mm, the tensor at the cog
        # in flange axes [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] kg m2 (targets/ur.toml cites the form). Without an inertia
        # the call keeps the one set before (set_payload_mass, set_payload_cog) or, set_payload and
        # set_target_payload without it, a point mass (zero tensor: the manual's default not confirmed here).
        mass = float(num(mass, where, "mass"))
        if not mass >= 0:
            raise RunError(f"{where}: {name}: payload mass {mass} kg")
        before = fr.m.state.payload or (0.0,) * 10
        if cog is None:  # the centre of gravity set before, else the flange's centre
            cog_mm = list(before[1:4])
        else:
            cog_mm = [MM_PER_M * float(v) for v in vector(cog, where, "centre of gravity")]
        if inertia is None:
            tensor = list(before[4:]) if name in KEEPS_INERTIA else [0.0] * 6
        else:
            tensor = [float(v) for v in joints(inertia, where, 6, "inertia")]
        fr.m.state.payload = _flat_load(mass, *cog_mm, *tensor)

    def set_target_payload(fr, args, kwargs, where):
        # set_target_payload(m, cog, inertia, transition_time): kg, m, kg m2 (URScript manual)
        params = ("m", "cog", "inertia", "transition_time")
        a = arguments("set_target_payload", params, {"inertia": None, "transition_time": 0.0}, args, kwargs, where)
        _payload(fr, a["m"], a["cog"], where, "set_target_payload", a["inertia"])

    def set_payload(fr, args, kwargs, where):
        a = arguments("set_payload", ("m", "cog"), {"cog": None}, args, kwargs, where)
        _payload(fr, a["m"], a["cog"], where, "set_payload")

    def set_payload_mass(fr, args, kwargs, where):
        a = arguments("set_payload_mass", ("m",), {}, args, kwargs, where)
        _payload(fr, a["m"], None, where, "set_payload_mass")

    def set_payload_cog(fr, args, kwargs, where):
        a = arguments("set_payload_cog", ("CoG",), {}, args, kwargs, where)
        mass = (fr.m.state.payload or (0.0,))[0]
        _payload(fr, mass, a["CoG"], where, "set_payload_cog")

    def get_tcp_offset(fr, args, kwargs, where):
        arguments("get_tcp_offset", (), {}, args, kwargs, where)
        tcp = fr.m.state.tcp
        if tcp is None:
            raise RunError(f"{where}: get_tcp_offset: the installation's TCP is not known here (the program sets none)")
        return URPose(tcp)

    def pose_now(fr, where: str, name: str) -> np.ndarray:
        mode = fr.m.state.speed
        if mode is not None and mode.name == "speedl":
            return mode.pose_at(fr.m.clock)
        return _tool_pose(fr, where, name)

    def get_target_tcp_pose(fr, args, kwargs, where):
        arguments("get_target_tcp_pose", (), {}, args, kwargs, where)
        return URPose(posemath.ur_from_matrix(pose_now(fr, where, "get_target_tcp_pose")))

    def get_actual_tcp_pose(fr, args, kwargs, where):
        # the TCP in the base frame (m, rotation vector) "based on the actual robot encoder readings"
        # (URScript manual, e-Series 15.6): where the arm is at the clock (on a move's path at a thread's
        # cycle), with the TCP active now
        arguments("get_actual_tcp_pose", (), {}, args, kwargs, where)
        machine = fr.m
        machine.arm.resolve()
        if machine.state.speed is not None:
            return URPose(posemath.ur_from_matrix(pose_now(fr, where, "get_actual_tcp_pose")))
        found, tcp2flange = (None, None) if machine.watching is None else machine.watching.pose_at(machine.clock)
        # the flange there, with the TCP active now
        if found is None:
            found = _tool_pose(fr, where, "get_actual_tcp_pose")
        else:
            found = found @ np.linalg.inv(tcp2flange) @ machine.arm.tcp2flange
        return URPose(posemath.ur_from_matrix(found))

    def get_actual_joint_positions(fr, args, kwargs, where):
        if args or kwargs:
            arguments("get_actual_joint_positions", (), {}, args, kwargs, where)
        return [f32(v) for v in np.radians(fr.m.arm.actual(where))]

    def get_forward_kin(fr, args, kwargs, where):
        a = arguments("get_forward_kin", ("q", "tcp"), {"q": None, "tcp": None}, args, kwargs, where)
        arm = fr.m.arm
        if arm.arm is None:
            raise RunError(f"{where}: get_forward_kin needs the arm's kinematics (name the arm: --robot)")
        q = arm.actual(where) if a["q"] is None else np.degrees(joints(a["q"], where, 6, "get_forward_kin q"))
        tcp2flange = arm.tcp2flange if a["tcp"] is None else matrix(a["tcp"], where, "tcp")
        return URPose(posemath.ur_from_matrix(arm.arm.kin.fk(np.asarray(q, dtype=float)) @ tcp2flange))

    def inverse_kin(name: str, pose: str, fr, args, kwargs, where, near_unknown):
        """The IK built-ins' common part (the same parameters, URScript manual): the solution nearest qnear (deg),
        or nearest near_unknown(arm) where qnear is not given; its branch."""
        params = (pose, "qnear", "maxPositionError", "maxOrientationError", "tcp")
        defaults = {"qnear": None, "maxPositionError": 1e-10, "maxOrientationError": 1e-10, "tcp": None}
        a = arguments(name, params, defaults, args, kwargs, where)
        arm = fr.m.arm
        if arm.arm is None:
            raise RunError(f"{where}: {name} needs the arm's kinematics (name the arm: --robot)")
        near = np.degrees(joints(a["qnear"], where)) if a["qnear"] is not None else near_unknown(arm)
        tcp2flange = arm.tcp2flange if a["tcp"] is None else matrix(a["tcp"], where, "tcp")
        solutions = solve.branches(arm.arm, solve.flange_poses(matrix(a[pose], where, pose), tcp2flange))
        return arm, solve.nearest(arm.arm, solutions, near)

    def get_inverse_kin(fr, args, kwargs, where):
        # the solution nearest qnear (rad), a runtime exception when there is none (URScript manual)
        def current(arm):
            near = arm.current(where)
            if near is None:
                raise RunError(f"{where}: get_inverse_kin without qnear before the arm's joints are known")
            return near

        arm, (q, branch) = inverse_kin("get_inverse_kin", "x", fr, args, kwargs, where, current)
        if np.isnan(q).any():
            raise RunError(f"{where}: get_inverse_kin: no solution (the pose is out of reach)")
        out = [f32(v) for v in np.radians(q)]
        remember_joint_target(arm.arm, np.degrees(np.array([float(v) for v in out])), branch)  # as movej reads it
        return out

    def get_target_waypoint(fr, args, kwargs, where):
        # "the target waypoint of the active move" (the same pose during the whole move); a statement runs when
        # the arm has arrived (moves return on arrival), so it is the last move's target, as get_target_tcp_pose
        arguments("get_target_waypoint", (), {}, args, kwargs, where)
        return URPose(posemath.ur_from_matrix(pose_now(fr, where, "get_target_waypoint")))

    def at_rest(name: str, count: int):
        """A speed reading: zero while the arm stands (a statement after a move runs once it arrived); refused
        while it moves (a thread's reading during a move, a speedl / speedj: speeds are not simulated)."""

        def read(fr, args, kwargs, where):
            arguments(name, (), {}, args, kwargs, where)
            if fr.m.moving or fr.m.state.speed is not None:
                raise RunError(f"{where}: {name} while the arm moves: speeds along a move are not simulated")
            return [f32(0.0)] * count

        return read

    def tool_contact(fr, args, kwargs, where):
        # the number of time steps back to the moment before contact, 0 without contact (URScript manual): no
        # contact force is simulated (get_tcp_force is the zero wrench), so never a contact here
        a = arguments("tool_contact", ("direction",), {}, args, kwargs, where)
        joints(a["direction"], where, 6, "tool_contact direction")
        return 0

    def get_inverse_kin_has_solution(fr, args, kwargs, where):
        # whether get_inverse_kin would find a solution for the pose (same parameters, URScript manual)
        _arm, (q, _branch) = inverse_kin(  # any branch and turn within the limits
            "get_inverse_kin_has_solution", "pose", fr, args, kwargs, where, lambda arm: np.zeros(6)
        )
        return not np.isnan(q).any()

    def get_tcp_force(fr, args, kwargs, where):
        arguments("get_tcp_force", (), {}, args, kwargs, where)
        return [f32(0.0)] * 6  # modelled: no external force on the tool (see above)

    def is_steady(fr, args, kwargs, where):
        arguments("is_steady", (), {}, args, kwargs, where)
        return not fr.m.moving and fr.m.state.speed is None  # moves return on arrival: at rest after each

    return {
        "movej": move("movej"),
        "movel": move("movel"),
        "movep": move("movep"),
        "speedl": speed("speedl"),
        "speedj": speed("speedj"),
        "stopl": stop("stopl"),
        "stopj": stop("stopj"),
        "servoj": servoj,
        "set_tcp": set_tcp,
        "set_payload": set_payload,
        "set_payload_mass": set_payload_mass,
        "set_payload_cog": set_payload_cog,
        "set_target_payload": set_target_payload,
        "get_tcp_offset": get_tcp_offset,
        "get_target_tcp_pose": get_target_tcp_pose,
        "get_actual_tcp_pose": get_actual_tcp_pose,
        "get_actual_joint_positions": get_actual_joint_positions,
        "get_target_joint_positions": get_actual_joint_positions,
        "get_forward_kin": get_forward_kin,
        "get_inverse_kin": get_inverse_kin,
        "get_tcp_force": get_tcp_force,
        "get_target_waypoint": get_target_waypoint,
        "get_target_tcp_speed": at_rest("get_target_tcp_speed", 6),
        "get_actual_tcp_speed": at_rest("get_actual_tcp_speed", 6),
        "get_target_joint_speeds": at_rest("get_target_joint_speeds", 6),
        "get_actual_joint_speeds": at_rest("get_actual_joint_speeds", 6),
        "tool_contact": tool_contact,
        "get_inverse_kin_has_solution": get_inverse_kin_has_solution,
        "is_steady": is_steady,
    }
