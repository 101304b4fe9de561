"""Verify's judgement of a pick-from-belt run: where each part really was when the program acted on it."""

from __future__ import annotations

import numpy as np

from codegen.controllers import get_target
from codegen.kinds.conveyor.kind import KIND
from codegen.kinds.conveyor.native import margin_mm
from codegen.kinds.conveyor.plan import GRIP
from codegen.kinds.conveyor.program import (
    EARLY,
    FLUSHED,
    LOST,
    NOT_HELD,
    SKIPPED,
    STOPPED,
    TOO_CLOSE,
    TOO_LATE,
    lead_seconds,
)
from codegen.kinds.conveyor.reach import follow_mm
from codegen.kinds.conveyor.section import conveyor_of
from codegen.model.io import signal_name
from codegen.poses import rotmat_from_zyx_deg
from codegen.sim.belt import part_pose, part_y
from codegen.sim.bus import SCALE
from codegen.verify.checks import TOLERANCES
from codegen.verify.checks import pose_errors as _pose_errors

SKIPS = (SKIPPED, TOO_LATE, TOO_CLOSE, LOST, EARLY, NOT_HELD, FLUSHED)  # the messages of a part given up


def tolerances_mm(cell, target) -> tuple[float, float]:
    """(along the belt, across it and in height): what the program can know of a part's place. Along:
    tracking knows the belt's travel in whole counts, once where tracking starts and once in the tracking
    offset (2 / |E|); a mechanical unit's tracking also scales the travel by its counts per metre, a whole
    number (its rounding over the tracking range's end); an intercept meets the part where it predicts it,
    within the gripper's capture range (capture_mm, the cell's). Across and in height: x and z as the queue
    carries them (exact in registers; in 0.1 mm on a 16-bit group: half of that); both plus the controller's
    float arithmetic."""
    conveyor, pick = conveyor_of(cell), conveyor_of(cell).pick
    floats = TOLERANCES[target.numbers][0]
    e = abs(conveyor.counts_per_mm)
    along = pick.capture_mm if pick.tracking[target.name] == "intercept" else 2.0 / e
    if target.name in pick.trigger_input:  # the count latched by a thread up to a frame after the trigger
        along += pick.belt_speed_max_mm_s * KIND.facts(target)["trigger"]
    if target.name in pick.unit:
        per_m = round(e * 1000.0)
        along += abs(1.0 - e * 1000.0 / per_m) * (conveyor.camera_offset_mm + pick.window_mm[1] + 1000.0)
    across = 0.0 if KIND.facts(target).get("names") else 0.5 / SCALE
    return along + floats, across + floats


def counted_y(cell, case, part, t: float) -> float:
    """Where the program, reading the PLC's counter in whole counts, finds the part at t."""
    bits = case.belt.counter_bits
    delta = (case.belt.count(t) - case.belt.count(part.seen_s)) % 2**bits
    if delta > 2 ** (bits - 1):
        delta -= 2**bits
    return -conveyor_of(cell).camera_offset_mm + delta / conveyor_of(cell).counts_per_mm


def _unit(unit, too_close: dict, lost: dict) -> str | None:
    """A part given up as too close to the one before only when the unit's queue ignored its sync; as lost only
    when it left the start window while WaitWObj waited for it."""
    if unit is None:
        return None if not too_close and not lost else "a part given up for a mechanical unit's queue, with none"
    for seq in too_close:
        if seq not in unit.ignored():
            return f"part {seq} given up as too close to the one before, yet the unit's queue took it"
    waited = {seq for seq, _t in unit.lost_waiting}
    for seq in lost:
        if seq not in waited:
            return f"part {seq} given up as lost from the start window, yet it was not"
    return None


def _numbered(trace, prefix: str) -> dict[int, float]:
    """Part number -> when the message naming it was written."""
    return {
        int(m[len(prefix) :]): t
        for m, t in zip(trace.messages, trace.message_times, strict=True)
        if m.startswith(prefix)
    }


class _Judge:
    def __init__(self, cell, target_name: str, case) -> None:
        self.cell, self.case = cell, case
        self.target = get_target(target_name)
        conveyor, pick = conveyor_of(cell), conveyor_of(cell).pick
        self.frame, self.pick = conveyor.frame(), pick
        self.camera_y = -conveyor.camera_offset_mm
        self.grip = np.eye(4)
        self.grip[:3, :3] = rotmat_from_zyx_deg(*pick.tool_orientation)
        self.mode = pick.tracking[target_name]
        self.tracking = self.mode == "native"
        self.along, self.across = tolerances_mm(cell, self.target)
        self.rot_tol = TOLERANCES[self.target.numbers][1]
        self.worst_pos = self.worst_rot = 0.0

    def part_at(self, part, t: float, dz: float = 0.0) -> np.ndarray:
        pose = part_pose(self.frame, self.case.belt, part, self.camera_y, t, self.grip)
        pose[:3, 3] += dz * self.frame[:3, 2]
        return pose

    def off(self, what: str, have: np.ndarray, want: np.ndarray) -> str | None:
        """have against want, the position error split along the belt, across it and in height."""
        error = self.frame[:3, :3].T @ (have[:3, 3] - want[:3, 3])
        pos, rot = _pose_errors(have.tolist(), want.tolist())
        self.worst_pos, self.worst_rot = max(self.worst_pos, pos), max(self.worst_rot, rot)
        if abs(error[1]) > self.along or max(abs(error[0]), abs(error[2])) > self.across or rot > self.rot_tol:
            return (
                f"{what}: {error[1]:+.4f} mm along the belt, {error[0]:+.4f} across, {error[2]:+.4f} in height, "
                f"{rot:.5f} deg (tolerance {self.along:.4f}, {self.across:.4f} mm)"
            )
        return None

    def clear(self, what: str, move) -> str | None:
        """A wait above the belt: its height in the belt frame approach_dz above the tallest part z_range_mm allows
        (a part before the one awaited may pass under it)."""
        want = self.pick.clear_mm
        height = float(self.frame[:3, 2] @ (move.tcp2base[:3, 3] - self.frame[:3, 3]))
        if abs(height - want) > self.across:
            return f"{what} (line {move.line}): {height:.4f} mm above the belt, not {want:g} (the tallest part's)"
        return None

    def gripped(self, part, t: float) -> np.ndarray:
        """Where the gripper grips the part at t: overtravel_mm below its top (the suction cup pressed on)."""
        return self.part_at(part, t, -self.pick.overtravel_mm)

    def beside(self, move, part, dz: float, anchor) -> np.ndarray:
        """Where a move to dz above the part's top should end: with tracking relative to the belt at the move's
        end; an intercept above the place it meets the part (anchor: the grip's pose, overtravel_mm below the top)."""
        if self.tracking:
            return self.part_at(part, move.end_time, dz)
        out = anchor.copy()
        out[:3, 3] += (dz + self.pick.overtravel_mm) * self.frame[:3, 2]
        return out


def judge(
    cell, target_name: str, case, trace, line, output: str, stop: str | None = None
) -> tuple[str | None, float, float]:
    """Every part taken once and in order; a part is skipped exactly when, as the program counted it at
    the skip's message, it was past the window's end (or, too late, within the descent's travel of the
    intercept point at the belt's fastest); each picked part is gripped where it really is at that
    moment (float64: the belt's travel since the camera saw it; overtravel_mm below its top), inside the window,
    after a straight descent of approach_dz and overtravel_mm along the belt's normal and before a straight lift that
    puts the held part's bottom at the clear height (Pick.lift_dz); each is put down at the place; the program ends at
    the line's stop; stop: the program stops with this message instead, once it has taken the part after the
    case's (a stop as it takes that part: the parts before it judged as any)."""
    j = _Judge(cell, target_name, case)
    pick, end = j.pick, j.pick.window_mm[1]
    one_count = 1.0 / abs(conveyor_of(cell).counts_per_mm)
    if trace.halted != (stop is not None) or (stop is not None and trace.halt_message != stop):
        return f"stopped: {trace.halt_message!r}, expected {stop!r}", 0.0, 0.0
    taken = list(line.taken)[: len(case.parts)] if stop is not None else list(line.taken)
    if taken != [p.seq for p in case.parts]:
        return f"parts taken {list(line.taken)}, expected {[p.seq for p in case.parts]} (each once, in order)", 0.0, 0.0
    parts = {p.seq: p for p in case.parts}
    skipped, too_late = _numbered(trace, SKIPPED), _numbered(trace, TOO_LATE)
    unit = getattr(line, "unit", None)
    too_close, lost, early = _numbered(trace, TOO_CLOSE), _numbered(trace, LOST), _numbered(trace, EARLY)
    flushed = _numbered(trace, FLUSHED)
    for seq, t in flushed.items():  # skipped as queued before the unit's queue was emptied at the start
        if unit is None or not unit.flushes or parts[seq].seen_s > unit.flushes[0]:
            return f"part {seq} given up as queued before the start, yet it was not", 0.0, 0.0
        # the program asks first whether a part is past the window's end (by the PLC's count, with its margin)
        if counted_y(cell, case, parts[seq], t) > pick.window_mm[1] + margin_mm(cell) + one_count:
            return f"part {seq} given up as queued before the start, yet it was past the window's end", 0.0, 0.0
    for seq in early:  # no count of the robot's own: it was seen before the program started
        if parts[seq].seen_s >= 0.0:
            return f"part {seq} given up as seen before the program started, yet the camera saw it after", 0, 0
    problem = _unit(unit, too_close, lost)
    if problem is not None:
        return problem, 0.0, 0.0
    for seq, t in skipped.items():
        if counted_y(cell, case, parts[seq], t) <= end - one_count:
            return (
                f"part {seq} skipped while it was in the window ({counted_y(cell, case, parts[seq], t):.1f} mm)",
                0,
                0,
            )
    for seq, t in {**skipped, **too_late, **lost}.items():  # given up after the arm moved for it: it was in the window
        read = line.taken.get(seq)
        moved = read is not None and any(read < m.end_time <= t for m in trace.moves)
        # it was gone already by the count the program read (as old as the PLC's copy was then)
        counted = read if read is None else read - line.age_s(read)
        if moved and counted_y(cell, case, parts[seq], counted) > end + one_count:
            y = counted_y(cell, case, parts[seq], counted)
            return f"part {seq} was past the window's end when read ({y:.1f} mm), yet the arm moved for it", 0, 0
    fastest = case.belt.speed_mm_s * (1.0 + abs(case.belt.wobble))
    for seq, t in too_late.items():  # already too close to the intercept point to come down onto it in time
        latest = pick.intercept_mm - lead_seconds(cell, j.target) * fastest - pick.capture_mm
        if part_y(case.belt, parts[seq], j.camera_y, t) < latest:
            return f"part {seq} given up as too late, in time for the intercept", 0.0, 0.0
    given_up = {*skipped, *too_late, *too_close, *lost, *early, *flushed}
    picked = [p for p in case.parts if p.seq not in given_up]
    closes = [o for o in trace.outputs if o.name == output and o.value == cell.io.value]
    closes = closes[1:] if case.held else closes  # the first: the grip asserted again on the part held at the start
    opens = [o for o in trace.outputs if o.name == output and o.value != cell.io.value][1:]  # after the first
    if len(closes) != len(picked) or len(opens) != len(picked):
        return f"{len(closes)} grips and {len(opens)} releases for {len(picked)} parts picked", 0.0, 0.0
    for part in picked:
        if counted_y(cell, case, part, line.taken[part.seq]) > end:
            return f"part {part.seq} picked although it was past the window's end when taken", 0.0, 0.0
    if unit is not None:  # each part picked on the object the unit connected for it
        connected = [seq for seq, _t in unit.connections]
        for part, close in zip(picked, closes, strict=True):
            on = [seq for seq, t in unit.connections if t <= close.time]
            if not on or on[-1] != part.seq:
                return f"part {part.seq} gripped while the work object follows part {on[-1] if on else None}", 0, 0
        if [p.seq for p in picked if p.seq in connected] != [p.seq for p in picked]:
            return f"parts picked {[p.seq for p in picked]}, the unit connected {connected}", 0.0, 0.0
    # the gripper holds the part grip_s after its output (an intercepting arm stands while the part travels
    # on; a tracking arm follows it, so the moment does not matter there)
    hold = 0.0 if j.tracking else case.grip_s
    for part, close, release in zip(picked, closes, opens, strict=True):
        y = part_y(case.belt, part, j.camera_y, close.time + hold)
        if not pick.window_mm[0] - j.along <= y <= end + j.along:
            return f"part {part.seq} gripped at y {y:.2f} mm, outside the window", j.worst_pos, j.worst_rot
        held = j.gripped(part, close.time + hold)
        problem = j.off(f"part {part.seq} gripped (line {close.line})", close.tcp2base, held)
        k = close.after_moves  # the moves commanded before the grip
        if problem is None and (k < GRIP[j.mode] or k >= len(trace.moves)):
            problem = f"part {part.seq}: no descent and lift around the grip"
        if problem is None:
            down, before, lift = trace.moves[k - 1], trace.moves[k - 2], trace.moves[k]
            if down.kind != "linear" or lift.kind != "linear":
                problem = f"part {part.seq}: the descent and the lift must be straight moves"
            else:
                problem = j.off(
                    f"part {part.seq}: above it before the descent (line {before.line})",
                    before.tcp2base,
                    j.beside(before, part, pick.approach_dz, down.tcp2base),
                ) or j.off(
                    f"part {part.seq}: the lift to the clear height (line {lift.line})",
                    lift.tcp2base,
                    j.beside(lift, part, pick.lift_dz, down.tcp2base),
                )
        if problem is None:  # after the moves around the grip: without the move above the part, that is the wait
            problem = j.clear(f"part {part.seq}: the wait for it", trace.moves[k - GRIP[j.mode]])
        if problem is not None:
            return problem, j.worst_pos, j.worst_rot
        pos, rot = _pose_errors(release.tcp2base.tolist(), pick.place.matrix().tolist())
        if pos > TOLERANCES[j.target.numbers][0] or rot > j.rot_tol:
            return f"part {part.seq} released {pos:.4f} mm, {rot:.5f} deg from the place", j.worst_pos, j.worst_rot
    if not trace.messages or trace.messages[-1] != (STOPPED if stop is None else stop):
        return (
            f"the program did not end at the line's stop (last message {trace.messages[-1:]})",
            j.worst_pos,
            j.worst_rot,
        )
    return None, j.worst_pos, j.worst_rot


def left_low(cell, target_name: str, case, trace, first: int, closes: list) -> str | None:
    """Where the arm stays after a straight move it follows with a joint move, or with none (the program ends, halts or
    waits for the next part there), from move `first` on: above the place, or at the clear height above the belt;
    only a lift with a part held (the move after a grip, its bottom at the clear height) is higher. Never at a part's
    approach height, below the tallest part the belt may bring."""
    j = _Judge(cell, target_name, case)
    above = j.pick.place.matrix().copy()
    above[2, 3] += j.pick.approach_dz
    held = {c.after_moves for c in closes}
    moves = trace.moves
    for i in range(first, len(moves)):
        if moves[i].kind != "linear" or i in held or (i + 1 < len(moves) and moves[i + 1].kind != "joint"):
            continue
        pos, _rot = _pose_errors(moves[i].tcp2base.tolist(), above.tolist())
        if pos > TOLERANCES[j.target.numbers][0]:
            problem = j.clear(f"the arm left after move {i + 1}", moves[i])
            if problem is not None:
                return problem
    return None


def not_held(cell, target_name: str, case, trace, output: str, first: int) -> tuple[str | None, float, float]:
    """A grip never confirmed (every target, every mode): no stop; the gripper's output set on the part where it
    really is, then back to release before the next move; that move straight up off the part to the clear height
    (with tracking still relative to the belt at its end, an intercept above the point it met it: the arm never left
    at the part's approach height, where the program could end, stop or wait for the next part); then the part skipped
    with a message, and the program on to the line's stop (never a stop on the running belt)."""
    j = _Judge(cell, target_name, case)
    part = case.parts[0]
    if trace.halted:
        return f"a part the gripper did not hold: stopped on the running belt ({trace.halt_message!r})", 0.0, 0.0
    events = [o for o in trace.outputs if o.name == output][1:]  # after the release at the start
    if len(events) != 2 or events[0].value != cell.io.value or events[1].value == cell.io.value:
        return f"the gripper's outputs {[(o.value, o.after_moves) for o in events]}: expected a grip, a release", 0, 0
    close, release = events
    k = close.after_moves
    if release.after_moves != k or k < first + GRIP[j.mode] or k >= len(trace.moves):
        return f"the grip after move {k}, the release after move {release.after_moves}: not both on the part", 0, 0
    hold = 0.0 if j.tracking else case.grip_s
    problem = j.off(f"part {part.seq} gripped (line {close.line})", close.tcp2base, j.gripped(part, close.time + hold))
    down, lift = trace.moves[k - 1], trace.moves[k]
    if problem is None and (down.kind != "linear" or lift.kind != "linear"):
        problem = f"part {part.seq}: the descent and the lift off the part must be straight moves"
    if problem is None:
        above = j.beside(lift, part, j.pick.clear_mm - part.z, close.tcp2base)
        problem = j.off(f"part {part.seq}: the lift off it, released (line {lift.line})", lift.tcp2base, above)
    problem = problem or j.clear(f"part {part.seq}: the wait for it", trace.moves[k - GRIP[j.mode]])
    if problem is not None:
        return problem, j.worst_pos, j.worst_rot
    said = _numbered(trace, NOT_HELD)
    if list(said) != [part.seq] or said[part.seq] < lift.end_time:
        return f"part {part.seq} not skipped with a message once the arm was off it ({trace.messages})", 0, 0
    if trace.messages[-1] != STOPPED:
        return f"the program did not end at the line's stop (last message {trace.messages[-1:]})", 0, 0
    return None, j.worst_pos, j.worst_rot


LOW_MM = 1.0  # a pose this far below the clear height counts as low over the belt (clear of the rounding of the moves)


def belt_zone(cell, target_name: str, trace) -> str | None:
    """The belt zone's output (where the cell names one): on over every move that starts or ends over the belt below
    the clear height (z_range_mm's top + approach_dz, belt frame; over the belt: within x_range_mm and the travel
    from the camera's line to the window's end and the follow, approach_dz around), and off at the run's end unless
    the arm is still low over the belt there. The PLC stops the belt on a robot's stop while it is on."""
    pick = conveyor_of(cell).pick
    if target_name not in pick.zone_output:
        return None
    name = signal_name(get_target(target_name), "output", pick.zone_output[target_name])
    events = [o for o in trace.outputs if o.name == name]
    base2belt = np.linalg.inv(conveyor_of(cell).frame())
    clear, dz = pick.z_range_mm[1] + pick.approach_dz, pick.approach_dz
    (x0, x1), end = pick.x_range_mm, pick.window_mm[1] + follow_mm(cell, target_name)

    def low(move) -> bool:
        if move is None or move.tcp2base is None:
            return False
        x, y, z, _ = base2belt @ move.tcp2base[:, 3]
        start = -conveyor_of(cell).camera_offset_mm - dz
        return z < clear - LOW_MM and x0 - dz <= x <= x1 + dz and start <= y <= end + dz

    def on_at(t: float) -> bool:
        state = False
        for event in events:
            if event.time <= t + 1e-9:
                state = event.value
        return state

    for i, move in enumerate(trace.moves):
        if not (low(move) or (i > 0 and low(trace.moves[i - 1]))):
            continue
        off = [e for e in events if move.start_time < e.time < move.end_time - 1e-9 and not e.value]
        if not on_at(move.start_time) or off:
            return f"the belt zone's output {name} off during move {i + 1} (line {move.line}), low over the belt"
    last = trace.moves[-1] if trace.moves else None
    if on_at(trace.clock) and not low(last):
        return f"the belt zone's output {name} left on at the end, the arm off the belt"
    return None


STRUCK_STEP_S = 0.01  # the moments a standing arm is checked against the parts moving under it


def struck(cell, target_name: str, case, trace) -> str | None:
    """No part left on the belt (given up: skipped, too late, not held) ever under the tool below its top: the tool a
    cylinder of the tool's radius_mm around the TCP, its tip the lowest point; the part a box of part_size_mm along the
    tool frame's axes as it lies on the belt (without a size: its centre), its top at z, apart from every other part.
    Each pose is checked from the
    end of its move until the next move starts (a move's lowest point is its end: the descents are straight down)."""
    j = _Judge(cell, target_name, case)
    size = np.zeros(3) if j.pick.part_size_mm is None else np.asarray(j.pick.part_size_mm, dtype=float)
    half = 0.5 * (np.abs(j.grip[:3, :3]) @ size)  # belt frame: across, along, up
    radius = cell.robot.tool.radius_mm if cell.robot is not None else 0.0
    at = max(p.seen_s for p in case.parts) if case.parts else 0.0

    def apart(p, q) -> bool:  # two parts' boxes side by side or one behind the other (the belt keeps their offset)
        dy = part_y(case.belt, p, j.camera_y, at) - part_y(case.belt, q, j.camera_y, at)
        return abs(p.x - q.x) >= 2.0 * half[0] or abs(dy) >= 2.0 * half[1]

    # a case that places parts closer than their boxes allow (the timing cases treat a part as a point) has no answer
    # here: only the parts that lie apart from every other are checked
    left = [
        p
        for p in case.parts
        if any(p.seq in _numbered(trace, prefix) for prefix in SKIPS)
        and all(apart(p, q) for q in case.parts if q is not p)
    ]
    base2belt = np.linalg.inv(j.frame)
    moves = trace.moves
    for i, move in enumerate(moves):
        if move.tcp2base is None:
            continue
        x, y, z, _ = base2belt @ move.tcp2base[:, 3]
        if z >= j.pick.z_range_mm[1]:
            continue
        until = moves[i + 1].start_time if i + 1 < len(moves) else move.end_time
        for t in [*np.arange(move.end_time, until, STRUCK_STEP_S), until]:
            for part in left:
                along = part_y(case.belt, part, j.camera_y, t)
                dx = max(abs(x - part.x) - half[0], 0.0)
                dy = max(abs(y - along) - half[1], 0.0)
                if z < part.z and dx * dx + dy * dy < radius * radius:
                    return (
                        f"the tool {part.z - z:.1f} mm into part {part.seq} (left on the belt) at {t:.3f} s, after "
                        f"move {i + 1} (line {move.line}): its tip {z:.1f} mm above the belt, {dy:.1f} mm from it "
                        "along the belt"
                    )
    return None
