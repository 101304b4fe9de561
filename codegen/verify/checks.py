"""The checks every trace of every kind gets: the stop, each move's pose, speed, zone, tool, payload and joints,
every output in order, what the program stores for later programs, the numbers of its log lines."""

from __future__ import annotations

import math
import re
from functools import lru_cache

import numpy as np

from codegen.controllers import get_target
from codegen.dialects import get_dialect
from codegen.dialects.core.trace import halt_text
from codegen.robot.expect import JOINT_TOLERANCE_DEG  # the joints' tolerance: why it is what it is
from codegen.verify.plan import TOOL_LOAD, Expectation
from codegen.world import loads

# Tolerances from the numeric model: a float32 controller over a +-2,000 mm workspace stores positions with a
# step of 1.2e-4 mm and angles with 1e-7 rad; a handful of such roundings through the correction stays far below
# these bounds, a wrong formula far above them.
TOLERANCES = {"float32": (0.005, 0.001), "float64": (1e-9, 1e-9)}  # mm, deg
# A payload's mass and centre of gravity as the program writes them: float32 (1e-5 relative) and 3 decimals
LOAD_TOLERANCE = (1e-3, 1e-5)
# Its inertia tensor at the centre of gravity (kg m2), entry by entry: the programs write each inertia number to 6
# decimals (5e-7 each; a tensor entry sums up to three of them, and the parallel-axis terms of centres written to
# 1e-4 mm add below 1e-6 for 30 kg a metre off), the principal axes' angles to 4 decimals of a degree or as a
# quaternion to 6 (2e-6 rad at most: 2 |I| 2e-6 more), and the mass to 3 decimals scales the whole by up to
# 5e-4 kg / m: INERTIA_ABS + |I|max (INERTIA_REL + MASS_HALF_STEP / m).
INERTIA_ABS, INERTIA_REL, MASS_HALF_STEP = 5e-6, 1e-5, 5e-4
NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?|(?<!\w)[-+]?(?:nan|inf)\b")


def pose_errors(a: list, b: list) -> tuple[float, float]:
    """Position distance (mm) and rotation angle (deg) between two 4x4 poses given as lists; the angle from
    ||Ra - Rb||_F = 2 sqrt(2) sin(angle / 2), exact for any angle."""
    (a0, a1, a2, _), (b0, b1, b2, _) = a, b
    position = math.dist((a0[3], a1[3], a2[3]), (b0[3], b1[3], b2[3]))
    distance = math.dist(a0[:3] + a1[:3] + a2[:3], b0[:3] + b1[:3] + b2[:3])  # Frobenius norm of Ra - Rb
    return position, math.degrees(2.0 * math.asin(min(1.0, distance / (2.0 * math.sqrt(2.0)))))


@lru_cache(maxsize=256)
def move_settings(target_name: str, kind: str, exact: bool, own_tool: bool, speed_mm_s, zone_mm, percent) -> dict:
    """What a target's facts and the plan ask of a move, as the interpreter records it (read once per target
    and segment, not per move of every case)."""
    target = get_target(target_name)
    return get_dialect(target.dialect).move_settings(
        target.program, kind, exact, own_tool, speed_mm_s, zone_mm, percent
    )


def log_numbers(messages: list[str], prefixes: tuple[str, ...]) -> list[float]:
    """The numbers of the log lines that start with one of the prefixes, in order."""
    out = []
    for message in messages:
        if message.startswith(prefixes):
            out.extend(float(n) for n in NUMBER.findall(message))
    return out


class Checker:
    """The common checks of one target's runs against a cell: build once per target, call check() per run."""

    def __init__(self, cell, target_name: str) -> None:
        self.cell = cell
        self.target = get_target(target_name)
        self.pos_tol, self.rot_tol = TOLERANCES[self.target.numbers]
        robot = cell.robot
        self.arm = None if robot is None else robot.arms.get(target_name)
        self.own_tool = robot is not None and robot.tool_given
        self.tool = None if robot is None else robot.tool
        self.tool_load = None if not self.own_tool else loads.of_tool(robot.tool, robot.tool_shaped).flat()
        self.tcp2flange = None if robot is None else robot.tool.tcp2flange

    def check(
        self, expected: Expectation, trace, log_prefixes: tuple[str, ...] = (), renames: dict | None = None
    ) -> tuple[str | None, list, list]:
        """(problem or None, position errors, orientation errors) of one run against one expectation; renames: the
        texts a given program changed (edits.message_renames): a stop with the message so changed is the same."""
        problem = self._stop(expected, trace, renames)
        if problem is not None:
            return problem, [], []
        problem, pos, rot = self._moves(expected, trace)
        if problem is not None:
            return problem, pos, rot
        problem = self._outputs(expected, trace) or self._stored(expected, trace)
        problem = problem or self._logged(expected, trace, log_prefixes)
        return problem, pos, rot

    # --- the stop ------------------------------------------------------------------------------
    @staticmethod
    def _stop(expected: Expectation, trace, renames: dict | None = None) -> str | None:
        if expected.halt is not None:
            if not trace.halted:
                return f"expected a stop ({expected.halt!r}), the program did not stop ({len(trace.moves)} moves)"
            if trace.halt_message != expected.halt and not (
                renames and trace.halt_message == renamed(expected.halt, renames)
            ):
                return f"stop message {halt_text(trace)!r}, expected {expected.halt!r}"
        elif trace.halted:
            return f"unexpected stop: {halt_text(trace)!r}"
        return None

    # --- the moves -----------------------------------------------------------------------------
    def _blends(self, planned, key: str) -> bool:
        """Whether a move's setting `key` is one that would differ on a move allowed to blend (its zone), i.e. a
        mismatch in it is a blend where the arm must stop, not, say, a changed speed."""
        zone = planned.zone_mm or 1.0
        passing = move_settings(
            self.target.name, planned.kind, False, self.own_tool, planned.speed_mm_s, zone, planned.joint_percent
        )
        stopping = move_settings(
            self.target.name, planned.kind, True, self.own_tool, planned.speed_mm_s, zone, planned.joint_percent
        )
        return passing.get(key) != stopping.get(key)

    def _moves(self, expected: Expectation, trace) -> tuple[str | None, list, list]:
        got, planned = trace.moves, expected.moves
        if len(got) != len(planned):
            return f"{len(got)} moves, expected {len(planned)}", [], []
        pos_errors, rot_errors = [], []
        target_name = self.target.name
        for i, (g, e) in enumerate(zip(got, planned, strict=True)):
            where = f"move {i + 1} ({e.name}, line {g.line})"
            if g.kind != e.kind:
                return f"{where} is {g.kind}, expected {e.kind}", pos_errors, rot_errors
            settings = move_settings(
                target_name, e.kind, e.exact, self.own_tool, e.speed_mm_s, e.zone_mm, e.joint_percent
            )
            for key, want in settings.items():
                have = g.settings.get(key)
                numbers = isinstance(want, float) and isinstance(have, float)
                if have != want and not (numbers and math.isclose(have, want, rel_tol=1e-6)):  # float32 values
                    stop = " (the arm must stop exactly at this pose)" if e.exact and self._blends(e, key) else ""
                    return f"{where}: {key} {_setting(have)}, expected {_setting(want)}{stop}", pos_errors, rot_errors
            if e.tcp2base is not None:
                pos, rot = pose_errors(g.tcp2base.tolist(), e.tcp2base.tolist())
                pos_errors.append(pos)
                rot_errors.append(rot)
                pos_tol, rot_tol = e.tolerance or (self.pos_tol, self.rot_tol)
                if not pos <= pos_tol or not rot <= rot_tol:
                    return (
                        f"{where}: position error {pos:.6f} mm, orientation error {rot:.6f} deg "
                        f"(tolerance {pos_tol} mm, {rot_tol} deg)",
                        pos_errors,
                        rot_errors,
                    )
        if self.arm is not None:
            problem = self._arm(expected, got)
            if problem is not None:
                return problem, pos_errors, rot_errors
        return None, pos_errors, rot_errors

    def _arm(self, expected: Expectation, got: list) -> str | None:
        """Each move's joints against the plan's (where it has them), the payload in force against the plan's,
        and the tool in force (the flange's pose from the joints against the TCP's) against the cell's tool."""
        if any(g.joints is None for g in got):
            i = next(i for i, g in enumerate(got) if g.joints is None)
            return f"move {i + 1} ({expected.moves[i].name}, line {got[i].line}): the arm's joints are not known"
        if not got:
            return None
        joints = np.array([g.joints for g in got])
        planned = expected.planned_joints() if expected.planned_joints is not None else None
        if expected.joints_checked:
            for i, e in enumerate(expected.moves):
                q = e.joints if planned is None else planned[i]
                if q is None:
                    continue
                error = float(np.max(np.abs(joints[i] - q)))
                if not error <= JOINT_TOLERANCE_DEG:
                    return (
                        f"move {i + 1} ({e.name}, line {got[i].line}): the arm ends at joints {_text(joints[i])}, the "
                        f"controller's rule gives {_text(q)} ({error:.3f} deg apart; tolerance "
                        f"{JOINT_TOLERANCE_DEG} deg)"
                    )
        if self.tool_load is not None:
            for i, (g, e) in enumerate(zip(got, expected.moves, strict=True)):
                want = self.tool_load if e.payload == TOOL_LOAD else tuple(e.payload)
                have = g.settings.get("load")
                problem = _load_problem(have, want)
                if problem is not None:
                    return f"move {i + 1} ({e.name}, line {g.line}): the payload in force {problem}"
        if self.tcp2flange is None:
            return None
        return self._tools(expected, got, joints)

    def _tools(self, expected: Expectation, got: list, joints: np.ndarray) -> str | None:
        """The tool in force at every move, all moves at once: tcp2flange = flange2base^-1 tcp2base."""
        checked = [i for i, e in enumerate(expected.moves) if e.tool is not None]
        if not checked:
            return None
        flange2base = self.arm.kin.fk(joints[checked])
        tcp2base = np.array([got[i].tcp2base for i in checked])
        rotation = np.swapaxes(flange2base[:, :3, :3], 1, 2)  # a rigid transform's inverse
        tool_rot = rotation @ tcp2base[:, :3, :3]
        tool_pos = np.einsum("nij,nj->ni", rotation, tcp2base[:, :3, 3] - flange2base[:, :3, 3])
        want = np.array(
            [self.tcp2flange if isinstance(expected.moves[i].tool, str) else expected.moves[i].tool for i in checked]
        )
        pos = np.linalg.norm(tool_pos - want[:, :3, 3], axis=1)
        frobenius = np.linalg.norm((tool_rot - want[:, :3, :3]).reshape(len(checked), 9), axis=1)
        rot = np.degrees(2.0 * np.arcsin(np.minimum(1.0, frobenius / (2.0 * np.sqrt(2.0)))))
        for k, i in enumerate(checked):
            e = expected.moves[i]
            pos_tol = self.pos_tol if e.tool_tolerance is None else e.tool_tolerance
            if not pos[k] <= pos_tol or not rot[k] <= self.rot_tol:
                offset = tool_pos[k] - want[k][:3, 3]
                whose = "the cell's" if isinstance(e.tool, str) else "the one planned"
                return (
                    f"move {i + 1} ({e.name}, line {got[i].line}): the tool in force is not {whose}: its TCP "
                    f"{_text(offset, 3)} mm from it (flange frame), turned {rot[k]:.4f} deg"
                )
        return None

    # --- outputs, stored data, log -----------------------------------------------------------
    @staticmethod
    def _outputs(expected: Expectation, trace) -> str | None:
        """Every digital output the run set, in order, against the plan's: name, value, after which move, and
        never while the arm moves."""
        if expected.outputs is None:
            return None
        got, want = trace.outputs, expected.outputs
        if expected.output_names is not None:  # the others are a device's protocol (a queue's bits): its to judge
            got = [event for event in got if event.name in expected.output_names]
        for i, event in enumerate(got):
            if i >= len(want):
                return (
                    f"output {event.name} (line {event.line}) set to {event.value} after move {event.after_moves}: "
                    "not in the plan"
                )
            w = want[i]
            if (event.name, event.value, event.after_moves) != (w.name, w.value, w.after_moves):
                return (
                    f"output {event.name} (line {event.line}) set to {event.value} after move {event.after_moves}, "
                    f"expected {w.name} set to {w.value} after move {w.after_moves} ({w.what})"
                )
            if event.moving:
                return f"output {event.name} (line {event.line}) set while the arm moves: it must wait until it stands"
        if len(got) < len(want):
            missing = want[len(got)]
            return f"output {missing.name} never set to {missing.value} ({missing.what}); {len(got)} of {len(want)} set"
        return None

    @staticmethod
    def _stored(expected: Expectation, trace) -> str | None:
        for item in expected.stored:
            have = _kept(trace.kept, item.name)
            if have is None:
                have = item.if_unset
            if not _same_value(have, item.value, item.tolerance):
                want = _shown(item.value)
                return f"{item.name} holds {_shown(have)} when the program ends, expected {want} ({item.what})"
        return None

    def _logged(self, expected: Expectation, trace, prefixes: tuple[str, ...]) -> str | None:
        if expected.logged is None:
            return None
        numbers = log_numbers(trace.messages, prefixes)
        if len(numbers) != len(expected.logged):
            return f"log line has {len(numbers)} numbers, expected {len(expected.logged)}: {trace.messages!r}"
        for have, (name, want, tolerance) in zip(numbers, expected.logged, strict=True):
            if not abs(have - want) <= tolerance:
                return f"logged {name} = {have}, expected {want:.6f} (tolerance {tolerance})"
        return None


def _kept(kept: dict, name: str):
    """A kept name's value, or a field of it ("name.field.field": a record's fields, in any case)."""
    first, *path = name.split(".")
    value = kept.get(first)
    for field in path:
        if not isinstance(value, dict):
            return None
        value = next((v for k, v in value.items() if str(k).lower() == field.lower()), None)
    return value


def _load_problem(have, want) -> str | None:
    """What differs between the load in force and the plan's (codegen.world.loads.Load.flat): mass and centre of
    gravity to float32 rounding or the written decimals (kg, mm), the inertia tensor at the centre of gravity in
    flange axes to the written decimals (kg m2); None: the same."""
    if have is None:
        return "is not set"
    absolute, relative = LOAD_TOLERANCE
    if len(have) != len(want) or any(
        abs(h - w) > absolute + relative * abs(w) for h, w in zip(have[:4], want[:4], strict=True)
    ):
        return f"is {_text(have[:4], 4)} (mass kg, centre of gravity mm), the plan's {_text(want[:4], 4)}"
    scale = max(abs(v) for v in want[4:])
    tolerance = INERTIA_ABS + scale * (INERTIA_REL + MASS_HALF_STEP / max(want[0], MASS_HALF_STEP))
    error = max(abs(h - w) for h, w in zip(have[4:], want[4:], strict=True))
    if error > tolerance:
        return (
            f"has the inertia {_text(have[4:], 6)} (Ixx, Iyy, Izz, Ixy, Ixz, Iyz kg m2 at the centre of gravity, "
            f"flange axes), the plan's {_text(want[4:], 6)} ({error:.2e} apart; tolerance {tolerance:.1e})"
        )
    return None


def _flat(value) -> list | None:
    if isinstance(value, dict):
        value = [value[k] for k in sorted(value)]
    if isinstance(value, list | tuple | np.ndarray):
        out = []
        for v in value:
            inner = _flat(v)
            if inner is None:
                return None
            out.extend(inner)
        return out
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
        return None
    return [float(value)]


def _same_value(have, want, tolerance: float) -> bool:
    a, b = _flat(have), _flat(want)
    if a is None or b is None:
        return have == want
    return len(a) == len(b) and all(abs(x - y) <= tolerance for x, y in zip(a, b, strict=True))


def renamed(text: str, renames: dict[str, str]) -> str:
    """text with a given program's texts in place of the generated one's (edits.message_renames)."""
    for old, new in renames.items():
        text = text.replace(old, new)
    return text


def _setting(value) -> str:
    """A move setting as a message shows it: an absent one (None) as "not set", never Python's None."""
    return "not set" if value is None else f"{value:g}" if isinstance(value, float) else str(value)


def _shown(value) -> str:
    flat = _flat(value)
    if flat is None:
        return repr(value)
    return "[" + ", ".join(f"{v:g}" for v in flat) + "]" if len(flat) != 1 else f"{flat[0]:g}"


def _text(q, decimals: int = 3) -> str:
    return "[" + ", ".join(f"{v:.{decimals}f}" for v in q) + "]"
