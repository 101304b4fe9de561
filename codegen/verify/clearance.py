"""verify's clearance check: each move of an interpreted trace swept against the cell's solids and the arm itself."""

# What a trace gives: per move its kind (joint, linear), its end joints (solved by the interpreter's arm), its end TCP
# pose, its line and file, and the dialect's settings (the blending zone). A move is followed from the joints before
# it (the start joints for the first) to its own: a joint move interpolating every axis, a linear move keeping the TCP
# on the straight line (the tool in force taken from the trace itself: the end pose's TCP in the flange frame), and
# where a move blends into the next, the corner between them; a circular move along the arc the run followed. The part
# is carried from the move after the gripper's output closed (or from the start, where the case starts holding one)
# until the move after it opened. What stands only for a while (a station's machine moved by the case's reading, the
# stack as built) and the part's shape come from the case's kind (Scene.staged), after each grip and release.

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from codegen.controllers import get_target
from codegen.dialects import get_dialect
from codegen.model import io as signals
from codegen.protocol import Stage
from codegen.verify.plan import SCENARIOS
from codegen.verify.programs import FRESH
from codegen.world import cell as world_cell
from codegen.world import proof
from codegen.world.engine import Scene
from codegen.world.sweep import (
    MoveClearance,
    Path,
    Unresolved,
    check_path,
    circular_path,
    joint_path,
    linear_path,
)

PER_CATEGORY = 8  # of a kind's own category of cases (a reading's corner, its random readings), this many are swept
ROUND_DEG = 1e-6  # joints this close count as the same move (the memo's key)


@dataclass(frozen=True)
class MoveLeast:
    """One move's least clearance: the distance at the samples (mm), what is guaranteed along the whole move
    (lower_bound), where the move is written (file:line), what it is, the body (link, tool or part) and the solid or
    link it came nearest."""

    distance: float
    lower_bound: float
    where: str
    what: str
    body: str
    other: str
    move: int = -1  # its index among the trace's moves

    def text(self, clearance_mm: float) -> str:
        """The verdict's words: the move, the body, the solid and the distance."""
        if not np.isfinite(self.distance):
            return f"{self.where}: the {self.what} cannot be followed: {self.other}"
        near = f"cuts {-self.distance:.1f} mm into" if self.distance < 0 else f"comes within {self.distance:.1f} mm of"
        return (f"{self.where}: the {self.what}: the {_body(self.body)} {near} {self.other} (clearance "
                f"{clearance_mm:g} mm)")


def _body(name: str) -> str:
    return name if name in ("tool", "part") else f"arm's {name}"


@dataclass(frozen=True)
class Gripper:
    """The output that closes the gripper on a part, as the trace names it, and the value that closes it."""

    output: str
    closed: bool = True


def selected(categories: list[str], scenarios: list[str]) -> list[bool]:
    """Which of a program's cases (their categories and scenarios, in the kind's order) verify sweeps: every case of
    a common scenario (away from home, a stop's way home, a part held, a device's silence ...), and of each other
    category PER_CATEGORY spread evenly over its cases (a kind's corners and limits of the reading's envelope, its
    random readings): the same cases whatever the workers and chunks."""
    counts: dict[str, int] = {}
    for category in categories:
        counts[category] = counts.get(category, 0) + 1
    seen: dict[str, int] = {}
    out = []
    for category, scenario in zip(categories, scenarios, strict=True):
        k = seen[category] = seen.get(category, -1) + 1
        step = max(1, -(-counts[category] // PER_CATEGORY))
        out.append(scenario in SCENARIOS or k % step == 0)
    return out


def for_program(cell, target_name: str, filename: str, kind: str | None = None) -> TraceClearance | None:
    """The check of one program of the cell on a target: its arm among the cell's solids, with what the program's
    kind (its name; None: any kind's) sets up in each case (Scene.staged: its solids that stand only for a while,
    the part it carries); None where the cell gives no arm for the target."""
    if cell.robot is None or target_name not in cell.robot.arms or not cell.robot.arms[target_name].links:
        return None
    target = get_target(target_name)
    kinds = [cell.kinds[kind]] if kind is not None else list(cell.kinds.values())
    part = next((p for p in (k.scene.carried(cell) for k in kinds) if p is not None), None)
    free = world_cell.scene_of(cell, target_name)
    scenes = {False: free, True: free if part is None else world_cell.scene_of(cell, target_name, part)}
    gripper, feedback = None, None
    if cell.io is not None and target_name in cell.io.output:
        gripper = Gripper(signals.signal_name(target, "output", cell.io.output[target_name]), cell.io.value)
    if cell.io is not None and target_name in cell.io.feedback:
        feedback = signals.signal_name(target, "input", cell.io.feedback[target_name])
    dialect = get_dialect(target.dialect)
    home = cell.robot.home[target_name]
    staging = Staging(cell, target_name, kinds[0].scene if kind is not None else None, part)
    return TraceClearance(scenes, world_cell.clearance_mm(cell), dialect, filename, gripper, feedback, home, staging)


def held_at_start(check: TraceClearance, setup) -> bool:
    """Whether a case starts with the part in the gripper: the gripper's feedback input on at the start."""
    return setup is not None and check.feedback is not None and bool(setup.signals.get(check.feedback))


class Staging:
    """The scenes of a cell's program in its cases: the kind's solids that stand only for a while and the part it
    carries, at each point of a case's trace (Scene.staged), each scene built once."""

    def __init__(self, cell, target: str, scene=None, part=None):
        """scene: the kind's Scene (None: no case is known, the part is `part` and nothing else stands)."""
        self.cell, self.target, self.scene = cell, target, scene
        self.fixed = Stage((), {}, part)
        self.built: dict[tuple, Scene] = {}

    def along(self, case):
        """(grips, releases so far) -> Stage along the case's trace."""
        if self.scene is None or case is None:
            return lambda _grips, _releases: self.fixed
        return self.scene.staged(self.cell, self.target, case)

    def world(self, stage: Stage, carried: bool, resting: frozenset) -> Scene:
        key = (stage.key, carried, resting)
        if key not in self.built:
            part = stage.part if carried else None
            self.built[key] = world_cell.scene_of(self.cell, self.target, part, stage.solids, resting)
        return self.built[key]


class TraceClearance:
    """A program's traces swept against the cell's solids (and those a case's kind stands for a while), the part
    while the gripper holds it, every distinct move swept once (a memo by the move's kind, end joints, zone, what
    stands and the part)."""

    def __init__(self, scenes: dict[bool, Scene], clearance_mm: float, dialect, filename: str,
                 gripper: Gripper | None = None, feedback: str | None = None, home=None,
                 staging: Staging | None = None):
        """scenes: without and with the part (used where no staging is given); feedback: the gripper's feedback
        input as the program names it (on at the start: a part held); home: where a run starts that gives no start
        joints (default the arm's catalogue home); staging: the cell's scenes by case (None: scenes alone)."""
        self.scenes, self.clearance, self.dialect = scenes, clearance_mm, dialect
        self.filename, self.gripper, self.feedback = filename, gripper, feedback
        self.staging = staging
        self.arm = scenes[False].arm
        self.home = np.asarray(self.arm.home_deg if home is None else home, dtype=float)
        self.memo: dict[tuple, MoveLeast] = {}
        self._excluding: dict[tuple, Scene] = {}  # a scene with the pairs where the gripper acts left out
        self.swept = 0  # moves swept (memo misses)

    def check(self, trace, start_joints=None, held: bool = False, case=None
              ) -> tuple[MoveLeast | None, MoveLeast | None]:
        """(the trace's least clearance, its first move within the clearance or None). held: the case starts
        with a part in the gripper; case: the kind's verify case (what stands, what is carried; None: not known)."""
        moves = [m for m in trace.moves if m.joints is not None]
        if not moves:
            return None, None
        index = {id(m): i for i, m in enumerate(trace.moves)}
        holding = self._held(trace, len(trace.moves), held)
        along = self.staging.along(case) if self.staging is not None else None
        stages = self._stages(holding, held, along, [index[id(m)] for m in moves])
        q = self.home if start_joints is None else np.asarray(start_joints, dtype=float)
        least: MoveLeast | None = None
        first: MoveLeast | None = None
        resting = self._resting(trace, moves, index, holding, stages, q)
        for k, move in enumerate(moves):
            carried = holding[index[id(move)]]
            found = [self._move(q, move, carried, stages[k], resting[k])]
            zone = self.dialect.zone_mm(move.settings)
            if zone > 0 and k + 1 < len(moves):
                corner = self._corner(q, move, moves[k + 1], zone, carried, stages[k], resting[k] | resting[k + 1])
                if corner is not None:
                    found.append(corner)
            found = [replace(one, move=index[id(move)]) for one in found]
            for one in found:
                if least is None or one.distance < least.distance:
                    least = one
                if first is None and one.distance < self.clearance:
                    first = one
            q = np.asarray(move.joints, dtype=float)
        return least, first

    def _held(self, trace, count: int, held: bool) -> list[bool]:
        """Per move of the trace: whether the gripper holds the part during it (closed before the move set off)."""
        out = [held] * count
        if self.gripper is None:
            return out
        for event in sorted(trace.outputs, key=lambda e: e.after_moves):
            if event.name == self.gripper.output:
                state = event.value == self.gripper.closed
                for i in range(event.after_moves, count):
                    out[i] = state
        return out

    @staticmethod
    def _stages(holding: list[bool], held: bool, along, at: list[int]) -> list:
        """Per move (of those with joints): the Stage after the grips and releases before it (a grip: the gripper
        closed where it was open at the move before; one closed and opened again at the same pose is neither)."""
        if along is None:
            return [None] * len(at)
        grips = releases = 0
        state, counts = held, []
        for now in holding:
            grips += now and not state
            releases += state and not now
            state = now
            counts.append((grips, releases))
        return [along(*counts[i]) for i in at]

    def _scene(self, stage, carried: bool, resting: frozenset) -> Scene:
        if self.staging is not None and stage is not None:
            return self.staging.world(stage, carried and stage.part is not None, resting)
        scene = self.scenes[carried]
        if not resting:
            return scene
        key = (carried, resting)
        if key not in self._excluding:
            self._excluding[key] = scene.excluding(resting)
        return self._excluding[key]

    def _resting(self, trace, moves: list, index: dict, holding: list[bool], stages: list, q0: np.ndarray
                 ) -> list[frozenset]:
        """Per move (of those with joints), the (tool or part, solid) pairs not measured where the gripper acts (its
        output set while the arm stands at a pose): generate's rule (codegen.world.proof: along the straight moves
        next to that pose, the tool and the part against a solid within the clearance of them there), applied to
        the trace's moves, each with what stands and is carried during it."""
        out = self._flush(moves, q0, stages, [])
        if self.gripper is None:
            return out
        position = {index[id(m)]: k for k, m in enumerate(moves)}
        acts = [""] * len(moves)
        for event in trace.outputs:
            at = position.get(event.after_moves - 1)
            if event.name == self.gripper.output and at is not None:
                acts[at] = "grip" if event.value == self.gripper.closed else "release"
        if not any(acts):
            return out
        planned = tuple(
            proof.Move("linear" if m.kind != "joint" else "joint", np.asarray(m.joints, dtype=float), "",
                       carrying=holding[index[id(m)]], stage=str(k), grip=acts[k])
            for k, m in enumerate(moves)
        )

        def scene(carrying: bool, stage: str, exempt: frozenset) -> Scene:
            return self._scene(stages[int(stage)], carrying, exempt)

        near = proof._resting(None, proof.Path("", q0, planned), self.clearance, scene)  # generate's own rule
        flush = self._flush(moves, q0, stages, [k for k, act in enumerate(acts) if act])
        return [a | b | c for a, b, c in zip(out, near, flush, strict=True)]

    @staticmethod
    def _flush(moves: list, q0: np.ndarray, stages: list, acts: list[int]) -> list[frozenset]:
        """Per move, its stage's flush pairs (a kind's own check holds them) where the move belongs to the straight
        way to or from a pose where the gripper acts (acts: the moves that end there), or from where the run starts
        (a stop may leave the gripper at a place): the linear moves before it back to a joint move, those after it
        up to the next (a joint move to where the arm already stands counts as none)."""
        out = [frozenset()] * len(moves)
        if all(stage is None or not stage.flush for stage in stages):
            return out

        def straight(k: int, before: np.ndarray) -> bool:
            return moves[k].kind != "joint" or bool(np.allclose(before, moves[k].joints, atol=ROUND_DEG))

        joints = [q0, *(np.asarray(m.joints, dtype=float) for m in moves)]
        for anchor in [-1, *acts]:
            k = anchor
            while anchor >= 0 and k >= 0 and straight(k, joints[k]):  # back along the way in
                out[k] = out[k] | stages[k].flush
                k -= 1
            k = anchor + 1
            while k < len(moves) and straight(k, joints[k]):  # on along the way out
                out[k] = out[k] | stages[k].flush
                k += 1
        return out

    def _where(self, move) -> str:
        name = move.file or self.filename
        if name.startswith(FRESH):  # a module rendered from the cell: named by its file, as a single file's moves are
            name = name.rsplit("/", 1)[-1]
        return f"{name}:{move.line}"

    def _kind(self, move) -> str:
        """joint, linear or circular: how the move's path is followed."""
        if move.kind == "joint" or move.tcp2base is None:
            return "joint"
        if self.dialect.circular(move.kind, move.settings):
            return "circular" if getattr(move, "arc", None) is not None else "joint"
        return "linear"

    def _move(self, q0: np.ndarray, move, carried: bool, stage, resting: frozenset) -> MoveLeast:
        q1 = np.asarray(move.joints, dtype=float)
        kind = self._kind(move)
        key = (kind, carried, None if stage is None else stage.key, _rounded(q0), _rounded(q1), resting)
        if kind == "circular":
            key += (_rounded(move.arc.via[:3, 3]),)
        if key not in self.memo:
            what = {"joint": "joint move", "linear": "linear move", "circular": "circular move"}[kind]
            if kind == "joint" and move.kind != "joint" and move.tcp2base is not None:
                what = "circular move (its ends' joints: the run gives no arc)"
            self.memo[key] = self._sweep(self._path(q0, move), q0, carried, stage, move, what, resting)
        return self.memo[key]

    def _path(self, q0: np.ndarray, move) -> Path:
        kind = self._kind(move)
        if kind == "joint":
            return joint_path(q0, move.joints)
        tcp2flange = np.linalg.inv(self.arm.kin.fk(np.asarray(move.joints, dtype=float))) @ move.tcp2base
        tcp0 = self.arm.kin.fk(q0) @ tcp2flange
        if kind == "circular":
            return circular_path(self.arm, tcp2flange, tcp0, move.tcp2base, move.arc)
        return linear_path(self.arm, tcp2flange, tcp0, move.tcp2base)

    def _corner(self, q0: np.ndarray, move, after, zone: float, carried: bool, stage, resting: frozenset
                ) -> MoveLeast | None:
        """The blend's corner: from where the TCP enters the zone on this move to where it leaves it on the next,
        the joints a quadratic curve through the target's (its control point), so that the TCP cuts the corner
        within the zone as the controllers' blends do."""
        q1, q2 = np.asarray(move.joints, dtype=float), np.asarray(after.joints, dtype=float)
        tcp = [self.arm.kin.fk(q)[:3, 3] for q in (q0, q1, q2)]
        into = min(0.5, zone / max(float(np.linalg.norm(tcp[1] - tcp[0])), 1e-9))
        out = min(0.5, zone / max(float(np.linalg.norm(tcp[2] - tcp[1])), 1e-9))
        try:
            enter, leave = self._path(q0, move)(1.0 - into, q1), self._path(q1, after)(out, q1)
        except Unresolved:
            return None  # a line the arm cannot follow: the moves themselves report it
        key = ("corner", carried, None if stage is None else stage.key, _rounded(enter), _rounded(q1),
               _rounded(leave), resting)
        if key not in self.memo:
            path = _bezier(enter, q1, leave)
            what = f"blend's corner ({zone:g} mm zone)"
            self.memo[key] = self._sweep(path, enter, carried, stage, move, what, resting)
        return self.memo[key]

    def _sweep(self, path: Path, q0: np.ndarray, carried: bool, stage, move, what: str, resting: frozenset
               ) -> MoveLeast:
        self.swept += 1
        scene = self._scene(stage, carried, resting)
        try:
            result: MoveClearance = check_path(scene, path, q0, self.clearance)
        except Unresolved as exc:
            return MoveLeast(-np.inf, -np.inf, self._where(move), what, "arm", str(exc))
        return MoveLeast(result.distance, result.lower_bound, self._where(move), what, result.body, result.other)


def _bezier(q0: np.ndarray, control: np.ndarray, q1: np.ndarray) -> Path:
    """Joints along a quadratic curve from q0 to q1 pulled towards control (each axis monotone where the control lies
    between its ends, as at a blended corner that keeps turning the same way)."""
    return lambda s, _near: (1.0 - s) ** 2 * q0 + 2.0 * s * (1.0 - s) * control + s**2 * q1


def _rounded(q) -> tuple:
    return tuple(np.round(np.asarray(q, dtype=float) / ROUND_DEG).astype(np.int64).tolist())
