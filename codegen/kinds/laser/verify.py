"""The laser TCP program's cases against the simulated station, what it measured judged by the exact-edge reference."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from codegen.kinds.laser import program as lp
from codegen.kinds.laser.budget import FLOAT32_MM, TRUTH_MM, Tolerances
from codegen.kinds.laser.confirm import REFUSED, UNANSWERED, YES
from codegen.kinds.laser.drift import GrowingStation, drift_mm_s
from codegen.kinds.laser.reference import Expected, from_measured
from codegen.kinds.laser.section import laser_of
from codegen.model.io import signal_name
from codegen.sim.beam_station import BeamStation
from codegen.sim.beams import Pin

# A laser case's category -> the scenario it runs (codegen.verify.plan.SCENARIOS; the others are its own)
SCENARIO_OF = {
    "start_away": "start_away",
    "start_mid_cycle": "start_mid_cycle",
    "start_beside_column": "start_away",  # just outside the station's column: stopped before the arm moves
    "start_above_column": "start_away",
    "start_below_column": "start_away",
    "start_column_edge": "start_mid_cycle",  # just inside it: backs out, home, the whole calibration
    "sensors_silent": "device_silent",
    "tool_too_long": "reading_out_of_range",
    "steep_axis": "reading_out_of_range",
    "drifted_since_last": "reading_out_of_range",
    REFUSED: "operator_refuses",  # the operator answers No to writing the production tool (where the target asks)
    UNANSWERED: "operator_silent",  # nobody answers the question (the kind's own: the program waits, writes nothing)
    "tool_growing": "measurement_not_repeatable",  # the kind's own: the runs disagree (a tool warming up)
    "installation_without_tool": "production_tool_missing",  # the kind's own: the production tool not defined
}
STEP_LIMIT = 2_000_000  # a UR thread runs a few statements per 2 ms cycle for a minute of motion
NOISE_MM = 0.01  # the switching point's standard deviation (the sensors' noise the kind is built for)
HYSTERESIS_MM = 0.05  # the sensors' switching hysteresis (a setting of the sensor: five times its noise)
# The production tool before a run: the last calibration's TCP, this far from the tool as designed (flange frame,
# mm); every case starts from it: the program must neither move with it nor judge the TCP found against it
PREVIOUS_MM = (0.4, -0.3, 1.2)
ORIENTATION_DEG = 1e-3
AXIS_FLOAT32 = 2e-5  # a unit vector's components through a float32 square root and division


def rotation(axis, degrees: float) -> np.ndarray:
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    a = math.radians(degrees)
    return np.eye(3) + math.sin(a) * k + (1 - math.cos(a)) * k @ k


@dataclass(frozen=True)
class LaserCase:
    """The true tool (tcp2flange), the true sensor frame in the named one (None: as named), the sensors' noise
    and whether the TCP found is held to the truth (not where the sensor frame is wrong: the program cannot
    know it; the reference's answer is then what it must find)."""

    category: str
    tool: np.ndarray
    sensor_error: np.ndarray | None = None
    noise: float = NOISE_MM
    truth: bool = True
    seed: int = 0
    start: str = "home"
    dead: bool = False  # the sensors never switch (a sensor unplugged, its range set to nothing)
    previous: tuple | None = None  # the production tool's TCP before the run (mm; None: as designed + PREVIOUS_MM)
    answer: str | None = YES  # the operator's answer where the program asks before writing the tool (None: nobody)
    without_production_tool: bool = False  # the installation has no production tool (an installation variable)
    growing: bool = False  # the tool grows along its axis while calibrated: the runs disagree beyond spread_max_mm

    @property
    def scenario(self) -> str:
        return SCENARIO_OF.get(self.category, "nominal")


def cases(cell, seed: int = 0) -> list[LaserCase]:
    """The tool as its data says; one tilted 6 deg (its end face's rim 0.16 mm below its centre: the rim's
    correction matters beyond the 0.1 mm goal); three bent tools (the tip up to 1.5 mm off on each axis, the
    axis tilted up to 2 deg); a sensor frame 0.25 mm and 0.1 deg off the one the cell names; a tool 4.5 mm
    longer than its data (found, but farther than offset_max_mm: not written); a tool 7 mm shorter (the first
    circle passes under the tip: stopped); 9 mm longer (the tip in the beam where the search starts: stopped);
    one bent 35 deg (its axis steeper than offset_max_mm allows: stopped before the search); a tool that has
    bent a little at each calibration, now 0.8 offset_max_mm beyond the last result and 1.2 offset_max_mm beyond
    the tool as designed (stopped: the range is the tool as designed's, not the last result's).
    The tool as designed runs without noise (its tolerances are the tightest: a biased formula shows). Then the
    starts: away from home, where a stopped calibration leaves the arm, 1 mm beside, above and below the station's
    column and 1 mm inside its side; sensors that never switch; where the cell has more than one run, a tool that
    grows while it is calibrated (the runs disagree)."""
    rng = np.random.default_rng(seed)
    guess = cell.robot.tool.tcp2flange
    out = [LaserCase("as_designed", guess.copy(), noise=0.0, seed=seed)]  # quiet: the tightest tolerances
    tilted = guess.copy()
    tilted[:3, :3] = rotation((0.3, 1.0, 0.0), 6.0) @ tilted[:3, :3]
    out.append(LaserCase("tilted_6deg", tilted, seed=seed + 4))
    for i in range(3):
        tool = guess.copy()
        tool[:3, 3] += rng.uniform(-1.5, 1.5, 3)
        tool[:3, :3] = rotation(rng.normal(size=3), rng.uniform(0.2, 2.0)) @ tool[:3, :3]
        out.append(LaserCase("bent", tool, seed=seed + 1 + i))
    error = np.eye(4)
    error[:3, :3] = rotation((0.3, -0.5, 1.0), 0.1)
    error[:3, 3] = (0.2, -0.12, 0.08)
    bent = out[2].tool
    out.append(LaserCase("sensor_frame_error", bent, sensor_error=error, truth=False, seed=seed + 5))
    for category, dz in (("tool_too_long", 4.5), ("tool_too_short", -7.0), ("tip_in_the_beam", 9.0)):
        tool = guess.copy()
        tool[:3, 3] += guess[:3, 2] * dz
        out.append(LaserCase(category, tool, seed=seed + 6))
    steep = guess.copy()  # bent 35 deg, its tip 7 mm aside: the circles cross the axis 3.5 mm either side
    steep[:3, :3] = rotation((0, 1, 0), 35.0) @ steep[:3, :3]
    steep[0, 3] += 7.0
    out.append(LaserCase("steep_axis", steep, seed=seed + 7))
    offset = cell.sections["laser"].offset_max_mm
    drifted = guess.copy()
    drifted[:3, 3] += guess[:3, 2] * 1.2 * offset
    last = guess[:3, 3] + guess[:3, 2] * 0.4 * offset
    out.append(LaserCase("drifted_since_last", drifted, seed=seed + 8, previous=tuple(float(v) for v in last)))
    quiet = out[0]
    out += [
        replace(quiet, category="start_away", start="away"),
        replace(quiet, category="start_mid_cycle", start="mid_cycle"),
        replace(quiet, category="start_beside_column", start="column_side_out"),
        replace(quiet, category="start_above_column", start="column_top_out"),
        replace(quiet, category="start_below_column", start="column_bottom_out"),
        replace(quiet, category="start_column_edge", start="column_side_in"),
        replace(quiet, category="sensors_silent", dead=True),
    ]
    if cell.sections["laser"].runs > 1:  # the runs' spread: a tool growing while it is calibrated
        out.append(replace(quiet, category="tool_growing", growing=True))
    return out


def previous_tcp(cell, case: LaserCase) -> np.ndarray:
    """The production tool's TCP before the run (flange frame, mm): the last calibration's."""
    if case.previous is not None:
        return np.array(case.previous, dtype=float)
    return cell.robot.tool.tcp2flange[:3, 3] + np.array(PREVIOUS_MM)


def station_for(cell, target, case: LaserCase) -> BeamStation:
    laser = laser_of(cell)
    frame = laser.sensor_frame.matrix()
    if case.sensor_error is not None:
        frame = frame @ case.sensor_error
    inputs = {
        signal_name(target, "input", laser.beam_x[target.name]): "x",
        signal_name(target, "input", laser.beam_y[target.name]): "y",
    }
    range_mm = 0.0 if case.dead else 200.0
    options = {"range_mm": range_mm, "noise": case.noise, "hysteresis": HYSTERESIS_MM, "seed": case.seed}
    pin = Pin(case.tool, laser.pin_radius_mm)
    if case.growing:
        return GrowingStation(frame, pin, inputs, rate=drift_mm_s(laser), **options)
    return BeamStation(frame, pin, inputs, **options)


def _flat(value) -> list[float]:
    if isinstance(value, dict):
        value = [value[k] for k in sorted(value)]
    if isinstance(value, list | tuple | np.ndarray):
        return [x for v in value for x in _flat(v)]
    # a value never set (a data list's value left empty) is no number
    if not isinstance(value, int | float | np.floating | np.integer):
        return []
    return [float(value)]


def _halt_problem(want: Expected, trace) -> str | None:
    message = trace.halt_message or ""
    texts = {"tilt": lp.AXIS_TILT, "no_tip": lp.NO_TIP, "too_far": lp.TOO_FAR, "spread": lp.SPREAD}
    if want.halt is None:
        if trace.halted:
            return f"stopped with {message!r}; the reference writes the TCP"
        return None
    if not trace.halted:
        return f"ran to the end; the reference stops ({want.halt})"
    if want.halt.startswith("circle"):
        number = want.halt.split()[1]
        ok = message.startswith(lp.CIRCLE_EDGES.strip()) and message[len(lp.CIRCLE_EDGES) :].strip().startswith(number)
    else:
        ok = message.startswith(texts[want.halt])
    return None if ok else f"stopped with {message!r}; the reference stops with {want.halt}"


def _compare(label: str, got: list[float], want: list[float], tol: float) -> tuple[str | None, float]:
    if len(got) < len(want):
        return f"{label}: {len(got)} values, expected {len(want)}", 0.0
    worst = max((abs(g - w) for g, w in zip(got, want, strict=False)), default=0.0)
    if worst > tol:
        return f"{label} off by {worst:.4f} mm (tolerance {tol:.4f})", worst
    return None, worst


def runs_of(cell, kept: dict) -> np.ndarray:
    """Each run's TCP as the program kept it (runs x 3, mm)."""
    count = laser_of(cell).runs
    values = kept["runs"][: 3 * count]
    return np.array(values, dtype=float).reshape(-1, 3) if len(values) == 3 * count else np.zeros((0, 3))


def spread(runs: np.ndarray) -> float:
    """How far the farthest run's TCP lies from the runs' mean (mm)."""
    return float(np.max(np.linalg.norm(runs - runs.mean(axis=0), axis=1))) if len(runs) else 0.0


def _spread_problem(cell, trace, kept: dict) -> tuple[str | None, bool]:
    """(problem, whether the program rightly stopped for its runs' spread): a program whose runs lie farther apart
    than spread_max_mm must stop with SPREAD and write nothing; one whose runs agree must not."""
    laser = laser_of(cell)
    runs = runs_of(cell, kept)
    if len(runs) == 0:
        return f"the program kept no {laser.runs} runs' TCPs", False
    worst = spread(runs)
    stopped = trace.halted and (trace.halt_message or "").startswith(lp.SPREAD)
    if worst > laser.spread_max_mm + FLOAT32_MM and not stopped:
        return f"a run lies {worst:.4f} mm from the runs' mean (spread_max_mm {laser.spread_max_mm}): no stop", False
    if worst < laser.spread_max_mm - FLOAT32_MM and stopped:
        return f"stopped for the runs' spread, which is {worst:.4f} mm (spread_max_mm {laser.spread_max_mm})", False
    return None, stopped


def kept_values(target, trace) -> dict:
    return {key: _flat(trace.kept.get(name) or []) for key, name in lp.kept_names(target).items()}


def judge(cell, target, case: LaserCase, trace, want: Expected, tol: Tolerances) -> tuple[str | None, float, float]:
    """(problem, the worst difference from the reference in mm, |TCP - truth| in mm)."""
    kept = kept_values(target, trace)
    if want.halt is None:
        problem, stopped = _spread_problem(cell, trace, kept)
        if problem is not None:
            return problem, 0.0, 0.0
        if stopped:
            want = replace(want, halt="spread")
    problem = _halt_problem(want, trace)
    if problem is not None:
        return problem, 0.0, 0.0
    checks = []
    if want.halt is None or want.halt in ("too_far", "tilt", "no_tip", "spread"):
        edges = [v for circle in want.edges for beam in circle for v in beam]
        checks.append(("edges", kept["edges"][:16], edges, tol.edge))
    if want.centres is not None:
        checks.append(("centres", kept["centres"][:4], [v for c in want.centres for v in c], tol.centre))
    if want.tcp is not None:
        checks.append(("hits", kept["hits"][:6], [v for h in want.hits for v in h], tol.hit))
        checks.append(("axis", kept["axis"][:3], list(want.axis), tol.axis))
    if want.halt in (None, "spread"):
        checks.append(("tcp", kept["tcp"][:3], list(want.tcp), tol.tcp))
    worst = 0.0
    for label, got, exp, limit in checks:
        problem, off = _compare(label, got, exp, limit)
        worst = max(worst, off if label != "axis" else 0.0)
        if problem is not None:
            return problem, worst, 0.0
    circles = int(want.halt.split()[1]) if want.halt is not None and want.halt.startswith("circle") else 2
    if want.halt in (None, "too_far", "spread"):
        problem = _arithmetic_problem(cell, kept, want.halt == "too_far")
        if problem is not None:
            return problem, worst, 0.0
    problem = _moves_problem(cell, trace, circles)
    if problem is not None:
        return problem, worst, 0.0
    if want.halt is not None:
        return None, worst, 0.0
    truth = float(np.linalg.norm(np.array(kept["tcp"][:3]) - case.tool[:3, 3]))
    if case.truth and truth > TRUTH_MM:
        return f"the TCP found is {truth:.4f} mm from the true one (goal {TRUTH_MM} mm)", worst, truth
    return None, worst, truth


def _arithmetic_problem(cell, kept: dict, single: bool = False) -> str | None:
    """The program's centres, axis and last run's TCP against the method's float64 arithmetic on its own edges and
    hits (within its float32 arithmetic), and its TCP the runs' mean (single: a run stopped, its TCP the last)."""
    centres, axis, tcp = from_measured(cell, kept["edges"][:16], kept["hits"][:6])
    runs = runs_of(cell, kept)
    done = kept["tcp"][:3] if single else [float(v) for v in runs[-1]] if len(runs) else []
    mean = kept["tcp"][:3] if single else [float(v) for v in runs.mean(axis=0)] if len(runs) else []
    if len(done) != 3:
        return "the program kept no runs' TCPs"
    for label, got, want, limit in (
        ("centres", kept["centres"][:4], [v for c in centres for v in c], FLOAT32_MM),
        ("axis", kept["axis"][:3], list(axis), AXIS_FLOAT32),
        ("last run's tcp", done, list(tcp), FLOAT32_MM),
        ("tcp (the runs' mean)", kept["tcp"][:3], mean, FLOAT32_MM),
    ):
        worst = max(abs(g - w) for g, w in zip(got, want, strict=True))
        if worst > limit:
            return f"the program's {label} is not what its own edges and hits give (off by {worst:.5f})"
    return None


def _moves_problem(cell, trace, circles: int = 2) -> str | None:
    """Each circle's fixed poses (above, start, the half circle's end, back at the start) among the moves,
    in order, with the TCP's orientation `down` (base frame); the first `circles` of them (a program that
    stopped after a circle ran no more)."""
    laser = laser_of(cell)
    sensor2base = laser.sensor_frame.matrix()
    rot = sensor2base[:3, :3] @ lp.DOWN @ cell.robot.tool.tcp2flange[:3, :3]
    wanted = []
    for k in range(circles):
        points = lp.circle_points(laser, k)
        wanted += [(f"circle {k + 1} {n}", points[n]) for n in ("above", "start", "mid", "start")]
    moves = [m.tcp2base for m in trace.moves if m.tcp2base is not None]
    i = 0
    for label, point in wanted:
        base = sensor2base[:3, :3] @ np.array(point) + sensor2base[:3, 3]
        while i < len(moves) and np.linalg.norm(moves[i][:3, 3] - base) > FLOAT32_MM * 5:
            i += 1
        if i == len(moves):
            return f"no move to {label} {np.round(base, 3).tolist()} (in order)"
        cos = (np.trace(rot.T @ moves[i][:3, :3]) - 1) / 2
        angle = math.degrees(math.acos(min(1.0, max(-1.0, cos))))
        if angle > ORIENTATION_DEG * 10:
            return f"the move to {label} turns the tool {angle:.4f} deg from the flange's z along the sensor's -z"
        i += 1
    return None
