"""The pick-from-belt program: verified against simulated belts, mutations caught, the cell's [conveyor.pick]."""

from __future__ import annotations

import json
import re
from dataclasses import replace
from pathlib import Path

import pytest
from click.testing import CliRunner
from support.programs import edited, first, load_program, verify_one

from codegen.cli import main
from codegen.controllers import get_target
from codegen.kinds.conveyor.cases import cases
from codegen.kinds.conveyor.judge import tolerances_mm
from codegen.model.cell import CellError, load_cell
from codegen.render import render
from codegen.sim.belt import Belt, BeltLine, Part, part_y
from codegen.sim.bus import RegisterBus
from codegen.verify.runner import run_cases

CELL = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "conveyor" / "belt_pick.toml"


UR_QUEUE = get_target("ur").kind_tables["conveyor"]  # the part queue's registers (targets/ur.toml)
SUFFIX_END = {"ur": "end\n", "kuka": "END\n", "abb": "ENDMODULE\n"}  # the program file, not its data list


def _program(cell, old: str | None = None, new: str | None = None, target: str = "ur"):
    """The pick program for a target, every `old` in its program file replaced by `new`."""
    program = first(cell, target, "conveyor")
    if old is None:
        return program
    assert any(old in f.text for f in program.files), f"{old!r} not in the program"
    return edited(program, lambda text: text.replace(old, new) if text.endswith(SUFFIX_END[target]) else text)


def _verify(cell, program, first_mismatch: bool = False, only: tuple[str, ...] = ()):
    """The program's row over its cases (only: these categories alone, in this process)."""
    if only:
        chosen = [c for c in cases(cell) if c.category in only]
        return run_cases(cell, replace(program, row=0), chosen, 600_000, first_mismatch)
    return verify_one(cell, program, first_mismatch=first_mismatch)


def intercept_cell(tmp_path, **changes):
    """The bundled cell with ABB intercepting too (a controller without the Conveyor Tracking option)."""
    text = CELL.read_text().replace('abb = "native" }', 'abb = "intercept" }')
    for old, new in changes.items():
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "belt_pick.toml"
    path.write_text(text)
    return load_cell(path)


@pytest.mark.slow  # a whole verify run: in the slow set (the default run stays near 5 minutes)
def test_the_bundled_pick_programs_verify_with_every_part_where_it_is():
    """UR and ABB follow the belt; KUKA intercepts: each part gripped where it really is, within the count
    resolution and the trigger's latch (tracking) or the gripper's capture range (intercept)."""
    result = CliRunner().invoke(main, ["verify", str(CELL), "--json"])
    assert result.exit_code == 0, result.output
    reports = {r["target"]: r for r in json.loads(result.stdout)["conveyors"]}
    assert set(reports) == {"ur", "kuka", "abb"}
    # 26: the categories the next test lists, one case each
    assert all(r["mismatches"] == 0 and r["cases"] == 26 and r["parts_picked"] >= 15 for r in reports.values())
    # UR: two of its own decoder's ticks (ticks_per_mm 5.092647) and the latch's 2 ms at 40 mm/s
    assert reports["ur"]["pos_max_mm"] < 2 / 5.092647 + 40 * 0.002 and reports["abb"]["pos_max_mm"] < 0.35
    assert max(r["pos_max_mm"] for r in reports.values()) < 3.0


def test_the_cases_cover_a_varying_belt_a_counter_wrap_and_a_late_part():
    cell = load_cell(CELL)
    found = {c.category: c for c in cases(cell)}
    belts = {"constant_speed", "varying_speed", "rollover", "part_too_late", "fast_belt", "part_past_the_window"}
    scenarios = {"start_away", "start_mid_cycle", "gripper_silent", "gripper_stuck", "part_out_of_range"}
    scenarios |= {"gripper_sealed"}  # the cup sealed on the part as the program gives up the grip
    # the trigger's stray pulses, a part seen before the start; ABB's unit out of step with the PLC
    unit = {"unit_missed_sync", "stray_pulses", "seen_before_start"}
    # the robot's latch against the PLC's queue (UR); the counter's wrap with parts queued
    latch = {"latch_scale", "trigger_missed", "rollover_queued", "latch_overrun"}
    waits = {"part_too_close", "place_blocked", "belt_stands", "no_part", "tall_then_low", "stop_while_standing"}
    belts |= {"speeding_up"}  # the belt's fastest speed change during an intercept's lead
    assert set(found) == belts | scenarios | unit | latch | waits
    assert found["varying_speed"].belt.wobble > 0
    rollover = found["rollover"]  # the counter (running down: E < 0) passes 0 during the first part's travel
    first = rollover.parts[0]
    assert cell.sections["conveyor"].counts_per_mm < 0
    assert rollover.belt.count(first.seen_s) < rollover.belt.count(first.seen_s + 15.0)
    close = found["part_too_close"].parts  # the second part behind the first by half the minimum distance
    travel = found["part_too_close"].belt.travel_mm
    assert travel(close[1].seen_s) - travel(close[0].seen_s) == pytest.approx(50.0)
    pick = cell.sections["conveyor"].pick
    for case in found.values():  # the latencies within the cell's bounds
        low = pick.count_latency_s[0] + pick.motion_start_s[0]
        high = pick.count_latency_s[1] + pick.motion_start_s[1]
        assert low <= case.latency_s <= high and pick.grip_s[0] <= case.grip_s <= pick.grip_s[1]


def test_the_part_queue_lies_in_the_registers_a_plc_can_write():
    """A PROFINET or EtherNet/IP PLC writes integer and float registers 0..23 and boolean registers 0..63 only:
    [24:47] and [64:127] "cannot be accessed by FieldBus/PLC interfaces, since it is reserved for external RTDE
    clients" (URScript manual, e-Series, read_input_integer_register, read_input_boolean_register); the names
    that devices and --input use are the same registers."""
    kinds = {"seq": "input_integer", "count": "input_integer", "encoder": "input_integer", "x": "input_float"}
    kinds |= {"z": "input_float", "ack": "output_integer", "stop": "input_boolean"}
    registers, names = UR_QUEUE["registers"], UR_QUEUE["names"]
    assert set(registers) == set(names) == set(kinds)
    for role, kind in kinds.items():
        assert 0 <= registers[role] <= (63 if kind.endswith("boolean") else 23), role
        assert names[role] == f"{kind}_register_{registers[role]}", role
    program = _program(load_cell(CELL)).files[0].text
    for kind, number in re.findall(r"(?:read|write)_(\w+?)_register\((\d+)", program):
        assert f"{kind}_register_{number}" in names.values(), (kind, number)


# (old, new, what the verdict must say): each a program that moves somewhere else than the part is
MUTATIONS = [
    # followed backwards: gripped in the wrong place, or (the gripper's 45-55 ms on top) the lift out of the arm's
    # configuration, where the controller stops
    (
        "CNV_DIR = p[-0.499994000, 0.866029000,",
        "CNV_DIR = p[0.499994000, -0.866029000,",
        ("gripped", "a linear move would change the arm's configuration"),
    ),
    # the robot's own count not unwound across its wrap (the rollover case wraps it during a part's travel)
    (
        "encoder_unwind_delta_tick_count(0, encoder_get_tick_count(0) - latched)",
        "(encoder_get_tick_count(0) - latched)",
        "",
    ),
    ("    track_conveyor_linear(CNV_DIR, CNV_TICKS_PER_M)\n", "", "gripped"),
    ("CNV_CAMERA_Y = -1200.0970", "CNV_CAMERA_Y = -1190.0970", "gripped"),
    ("CNV_TICKS_PER_MM = 5.092647000", "CNV_TICKS_PER_MM = 5.112647000", "gripped"),
    ("> CNV_END:", "> CNV_END + 1000:", "past the window's end"),
    ("    movel(cnv_on_part(x, y, z, CNV_DZ), a=1.200, v=0.5000)\n", "", "above it before the descent"),
    ("CNV_DZ = 60.0000", "CNV_DZ = 0.0", "in height"),
    (
        "if cnv_own_y(mine) > CNV_END:",
        f"if cnv_own_y(mine) > CNV_END or read_input_boolean_register({UR_QUEUE['registers']['stop']}):",
        "in the window",
    ),
    # the part's place from the PLC's copy of a count (late by its cycle and the fieldbus), not the robot's own
    # encoder latched at the trigger: the gripper meets the part up to a millimetre behind it
    (
        "    y = cnv_own_y(mine)\n    set_standard_digital_out(1,",
        "    y = cnv_y(seen)\n    set_standard_digital_out(1,",
        "gripped",
    ),
    # no thread latching the trigger: no part has a count of the robot's own (seen since the start: a mismatch's stop)
    ("  cnv_latcher = run cnv_latch()\n", "", "the PLC's count disagree"),
]


# the intercepting programs (target, edits: (old, new) pairs, says): the lead ignored in the wait for the descent onto
# the part, the speed never measured again on a varying belt (measured once, at the first stage's start: neither at the
# second's nor at each read), no unwinding of the counter, the gripper's time left out of the lead
KUKA_ONCE = (
    "    CNV_MEASURE(SEEN, Y, V)\n    ; where the part is now",
    "    IF STAGE == 1 THEN\n      CNV_MEASURE(SEEN, Y, V)\n    ELSE\n      Y = CNV_Y(SEEN)\n    ENDIF\n"
    "    ; where the part is now",
)
ABB_ONCE = (
    "      cnv_measure seen, y, v;\n      ! where the part is now",
    "      IF stage = 1 THEN\n        cnv_measure seen, y, v;\n      ELSE\n        y := cnv_y(seen);\n      ENDIF\n"
    "      ! where the part is now",
)
INTERCEPT_MUTATIONS = [
    # the lead ignored in the wait: the arm starts down early and, landing where the part will be, comes down aslant
    ("kuka", (("      AHEAD = CNV_LEAD\n", "      AHEAD = 0.0\n"),), "mm along the belt"),
    (
        "kuka",
        (KUKA_ONCE, ("  V = (Y - CNV_YS[CNV_SLOT]) * 1000.0 / (T - CNV_TS[CNV_SLOT])\n", "")),
        "gripped",
    ),
    ("kuka", (("CNV_UNWIND(CNV_ENC - SEEN)", "(CNV_ENC - SEEN)"),), ""),
    ("abb", (("        ahead := CNV_LEAD;\n", "        ahead := 0;\n"),), "mm along the belt"),
    ("abb", (ABB_ONCE, ("    v := (y - cnv_ys{cnv_slot}) / (t - cnv_ts{cnv_slot});\n", "")), "gripped"),
    ("abb", (("cnv_unwind(GInput(giCnvEncoder) - seen)", "(GInput(giCnvEncoder) - seen)"),), ""),
]
# the lead without the gripper's time to hold the part (grip_s) is tests/kinds/test_conveyor_round2.py's: the bundled
# gripper's 0.05 s is 2 mm at 40 mm/s, within the 3 mm capture once the arm lands where the part is predicted


def _edited(cell, target: str, edits):
    """The pick program for a target with each (old, new) of edits made in its program file in turn."""
    program = first(cell, target, "conveyor")
    for old, new in edits:
        assert any(old in f.text for f in program.files), f"{old!r} not in the program"
        program = edited(
            program, lambda text, o=old, n=new: text.replace(o, n) if text.endswith(SUFFIX_END[target]) else text
        )
    return program


@pytest.mark.slow  # a whole verify per mutation: the slow set
@pytest.mark.parametrize(("target", "edits", "says"), INTERCEPT_MUTATIONS)
def test_an_intercept_that_misses_the_part_fails_verify(tmp_path, target, edits, says):
    cell = intercept_cell(tmp_path)
    # the counter wraps in the rollover case; the belt's own stand and the line without parts are
    # tests/kinds/test_conveyor_waits.py's (a speed never measured again is caught there first, unsaid)
    waits = ("belt_stands", "no_part", "stop_while_standing")
    unwind = any("UNWIND" in old.upper() for old, _new in edits)
    chosen = [c for c in cases(cell) if (c.category == "rollover" if unwind else c.category not in waits)]
    if not unwind:
        # the varying belt once more with its swing's period at 8 s: the bundled case's 7.18 s goes five times into the
        # first part's wait of about 36 s, so the speed at the first stage's start is that at its end by chance and a
        # speed measured only there is right; 8 s leaves them half a swing apart (and changes the speed slower, within
        # belt_accel_mm_s2 still)
        varying = next(c for c in chosen if c.category == "varying_speed")
        chosen.append(replace(varying, category="varying_8s", belt=replace(varying.belt, period_s=8.0)))
    source = _edited(cell, target, edits)
    report = run_cases(cell, replace(source, row=0), chosen, 600_000, True)
    assert report.mismatches > 0, report.summary()
    assert any(says in m for m in report.first_mismatches), report.first_mismatches


def test_a_belt_whose_counter_counts_up_verifies_on_every_target(tmp_path):
    """The bundled belt's counter runs down (E < 0); the same belt with a counter that runs up (E > 0)
    wraps the other way through 0 and is unwound by the other branch (ABB's intercept here: its native tracking
    has the unit count up whatever the counter does, tests/kinds/test_conveyor_native.py). Five parts, each picked or
    (an intercept whose gripper takes the cell's 45-55 ms, one) skipped for a reason verify accepts."""
    cell = intercept_cell(tmp_path, **{"counts_per_mm = -8.122679": "counts_per_mm = 8.122679"})
    for target in ("ur", "kuka", "abb"):
        report = _verify(cell, _program(cell, target=target), only=("rollover", "start_away"))
        figures = report.figures
        assert report.mismatches == 0 and figures.picked + figures.skipped == 5, report.summary()
        assert figures.picked >= 4, report.summary()


@pytest.mark.parametrize(("old", "new", "says"), MUTATIONS)
def test_a_program_that_misses_the_part_fails_verify(old, new, says):
    cell = load_cell(CELL)
    only = ("rollover",) if "unwind" in old else ()  # the counter wraps in that case
    report = _verify(cell, _program(cell, old, new), first_mismatch=True, only=only)
    assert report.mismatches > 0, report.summary()
    accepted = (says,) if isinstance(says, str) else says
    assert any(phrase in m for m in report.first_mismatches for phrase in accepted), report.first_mismatches


def test_the_tolerance_is_two_counts_of_travel_or_the_capture_range():
    """Along the belt 2 / |E| mm for tracking (the program knows the part's place in whole counts, at the
    start of tracking and in the tracking offset: 0.25 mm for the bundled belt's 8.12 counts per mm), for UR
    plus the belt's travel in a controller frame at its fastest (the thread latches the trigger up to a frame
    late), for ABB's unit plus its whole counts per metre's rounding over its tracking range; the gripper's
    capture range for an intercept; across and in height, x and z as the queue carries them (registers: exact;
    16-bit groups: 0.05 mm); plus the float32 arithmetic."""
    cell = load_cell(CELL)
    assert tolerances_mm(cell, get_target("ur")) == pytest.approx((2 / 8.122679 + 40 * 0.002 + 0.005, 0.005))
    assert tolerances_mm(cell, get_target("kuka")) == pytest.approx((3.005, 0.055))
    rounding = abs(1 - 8122.679 / 8123) * (1200.097 + 100.0 + 1000.0)
    assert tolerances_mm(cell, get_target("abb")) == pytest.approx((2 / 8.122679 + rounding + 0.005, 0.055))


def test_a_file_that_is_none_of_the_cells_programs_is_refused(tmp_path):
    """A program under another name would be judged by nothing: verify refuses it instead of passing."""
    (file,) = [f for f in render(load_cell(CELL), ["ur"]) if f.relpath.endswith(".script")]
    other = tmp_path / "other.script"
    other.write_text(file.text)
    result = CliRunner().invoke(main, ["verify", str(CELL), str(other)])
    assert result.exit_code == 2 and "other.script: not a program of belt_pick" in result.output


def test_the_simulated_belt_counts_and_wraps_on_its_own():
    """The belt's counter: whole counts of travel from its start, reduced to the counter's width; a
    varying speed still travels v t on average over a whole period."""
    belt = Belt(100.0, -8.0, 16, 100)
    assert belt.unwrapped_count(1.0) == 100 - 800
    assert belt.count(1.0) == 65536 - 700
    wobbly = Belt(100.0, 8.0, 32, 0, wobble=0.5, period_s=2.0)
    assert wobbly.travel_mm(2.0) == pytest.approx(200.0)
    assert wobbly.travel_mm(wobbly.time_at(123.0)) == pytest.approx(123.0, abs=1e-9)
    part = Part(1, 0.5, 0.0, 20.0)
    assert part_y(Belt(50.0, 8.0), part, -1000.0, 2.5) == pytest.approx(-900.0)


def test_the_interpreter_tracks_the_belt_from_the_moment_tracking_starts():
    """track_conveyor_linear: a pose commanded after the call is reached where the belt has carried it
    (ticks since the call / ticks per metre along the direction), also while the arm waits."""
    text = (
        "def t():\n"
        "  encoder_enable_pulse_decode(0, 1, 8, 9)\n"
        "  sleep(1.0)\n"
        "  track_conveyor_linear(p[0, 1, 0, 0, 0, 0], 8000.0)\n"
        "  movel(p[0.5, 0, 0.2, 0, 3.14159265, 0], a=1.2, v=0.25)\n"
        "  sleep(2.0)\n"
        "  set_standard_digital_out(0, True)\n"
        "  stop_conveyor_tracking()\n"
        "end\n"
    )
    program = load_program(get_target("ur"), text, "track", {})
    belt = Belt(100.0, 8.0, 16, 0)  # 800 counts per second: 100 mm/s
    line = BeltLine(belt, [], RegisterBus(UR_QUEUE["names"]))
    trace = program.run({}, devices=(line,))
    (move,) = trace.moves  # commanded at t = 1 s; a first move from an unknown pose takes 1 s: it ends at 2 s
    assert move.tcp2base[:3, 3] == pytest.approx([500.0, 100.0, 200.0], abs=1e-3)
    out = trace.outputs[0]  # after a 2 s sleep, still tracking: the belt carried the arm 200 mm further
    assert out.time == pytest.approx(4.0)
    assert out.tcp2base[:3, 3] == pytest.approx([500.0, 300.0, 200.0], abs=1e-3)


def test_a_direction_that_is_not_a_unit_vector_is_refused():
    text = (
        "def t():\n  encoder_enable_pulse_decode(0, 1, 8, 9)\n"
        "  track_conveyor_linear(p[0, 2, 0, 0, 0, 0], 8000.0)\nend\n"
    )
    program = load_program(get_target("ur"), text, "track", {})
    line = BeltLine(Belt(100.0, 8.0), [], RegisterBus(UR_QUEUE["names"]))
    with pytest.raises(Exception, match="unit vector"):
        program.run({}, devices=(line,))


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            "window_mm = [-150.0, 100.0]",
            "window_mm = [150.0, -150.0]",
            r"conveyor\.pick\.window_mm: expected \[low, high\]",
        ),
        ('abb = "native" }', 'abb = "native", dtrans = "intercept" }', r"tracking\.dtrans: not one of"),
        ('kuka = "intercept"', 'kuka = "native"', r"tracking\.kuka: 'native': what codegen builds for kuka: intercept"),
        ('ur = "native"', 'ur = "predicted"', r"conveyor\.pick\.tracking\.ur: expected one of"),
        ("intercept_mm = -75.0", "intercept_mm = 200.0", r"conveyor\.pick\.intercept_mm: must lie in the window"),
        ("encoder_inputs = { ur = [8, 9] }", "encoder_inputs = { ur = [8] }", r"conveyor\.pick\.encoder_inputs\.ur"),
        ("counts_per_mm = -8.122679\n", "", r"conveyor\.pick: needs the calibrated belt: counts_per_mm"),
        ("approach_dz = 60.0", "approach_dz = 0.0", r"conveyor\.pick\.approach_dz: must be in \(0, 1000\]"),
        (
            "encoder_inputs = { ur = [8, 9] }",
            "encoder_inputs = { ur = [8, 8] }",
            r"ur: expected two different inputs, got \[8, 8",
        ),
        (
            "encoder_inputs = { ur = [8, 9] }",
            "encoder_inputs = { ur = [0, 1] }",
            r"ur\[0\]: expected a whole number in 8\.\.",
        ),
        ("camera_offset_mm = 1200.097", "camera_offset_mm = 100.0", r"window_mm: must start downstream of the camera"),
        ("camera_offset_mm = 1200.097", "camera_offset_mm = 9000.0", r"allows 16384: bring the window closer"),
        ("capture_mm = 3.0", "capture_mm = 0.2", r"capture_mm: two counts of the encoder \(0\.25 mm\) exceed"),
        ("part_mass_kg = 0.8", "part_mass_kg = 0.0", r"conveyor\.pick\.part_mass_kg: must be in \(0, 1000\]"),
        ("part_mass_kg = 0.8 ", "# ", r"conveyor\.pick\.part_mass_kg: missing"),
        (', abb = "diCnvPlaceClear" }', " }", r"conveyor\.pick\.place_clear\.abb: missing"),
        ("min_gap_mm = 100.0", "min_gap_mm = 400.0", r"conveyor\.pick\.min_gap_mm: must be in \[0, 250\] mm"),
        (
            "trigger_input = { ur = 3 }",
            "trigger_input = { ur = 9 }",
            r"trigger_input\.ur: expected a whole number in 0",
        ),
        ("trigger_input = { ur = 3 }", "", r"conveyor\.pick\.trigger_input: missing ur"),
        ("timer = { kuka = 1 }", "timer = { kuka = 65 }", r"timer\.kuka: expected a whole number in 1\.\.64"),
        ('abb = "native" }', 'abb = "native" }\nunit = { abb = "CNV 1" }', r"conveyor\.pick\.unit\.abb: expected"),
        ("grip_s = [0.045, 0.055]", "grip_s = [0.055, 0.045]", r"conveyor\.pick\.grip_s: must be a duration"),
    ],
)
def test_a_bad_pick_table_is_refused_naming_the_key(tmp_path, old, new, message):
    text = CELL.read_text()
    assert old in text
    if old.startswith("counts_per_mm"):  # the calibration's keys come together: drop them all
        for key in ("counts_per_mm", "ticks_per_mm", "origin", "direction", "z_axis"):
            text = "\n".join(line for line in text.splitlines() if not line.startswith(key)) + "\n"
    else:
        text = text.replace(old, new)
    path = tmp_path / "cell.toml"
    path.write_text(text)
    with pytest.raises(CellError, match=message):
        load_cell(path)


def test_a_window_the_arm_cannot_follow_is_refused_at_generate(tmp_path):
    """900 mm upstream of the belt's origin lies 1.6 m from the UR10e's base (reach 1.3 m)."""
    from codegen.generate import GenerateError, check_envelope

    path = tmp_path / "cell.toml"
    path.write_text(CELL.read_text().replace("window_mm = [-150.0, 100.0]", "window_mm = [-900.0, 100.0]"))
    with pytest.raises(
        GenerateError, match=r"conveyor \(ur, UR10e\): above the part at x -50 z 5 mm, pose 1 of 12: out"
    ):
        check_envelope(load_cell(path), None)
    reports = check_envelope(load_cell(CELL), None)
    assert [r.poses for r in reports if hasattr(r, "poses")] == [2 * 2 * 3 * 12 + 2] * 3  # x, z, on/above/lifted; place


def test_a_tracking_arm_is_proven_as_far_as_it_may_follow_the_part(tmp_path):
    """UR follows the part past the window's end for the gripper's timeout and the lift: at the cell's
    fastest belt (belt_speed_max_mm_s) that is proven reachable too; at 2 m/s it is not (1.5 m further: beyond
    the arm's reach, or in another configuration). The cell tracks with UR alone here (at 2 m/s the KUKA's
    intercept is far over its timing budget)."""
    from codegen.generate import GenerateError, check_envelope
    from codegen.kinds.conveyor.reach import follow_mm

    cell = load_cell(CELL)
    # the grip's timeout and a release's (0.5 s each), the lift with a part held (its bottom from its top z to the clear
    # height, 80 + 60 mm): 140 mm at 250 mm/s and its ramps at movel's a = 1.2 m/s2 (250 / 1200 s)
    assert follow_mm(cell, "ur") == pytest.approx(40.0 * (2 * 0.5 + 140.0 / 250.0 + 250.0 / 1200.0))
    assert follow_mm(cell, "kuka") == 0.0
    path = tmp_path / "cell.toml"
    text = CELL.read_text().replace("belt_speed_max_mm_s = 40.0", "belt_speed_max_mm_s = 2000.0")
    text = text.replace(
        'tracking = { ur = "native", kuka = "intercept", abb = "native" }', 'tracking = { ur = "native" }'
    )
    path.write_text(
        text.replace('place_clear = { ur = 2, kuka = 19, abb = "diCnvPlaceClear" }', "place_clear = { ur = 2 }")
        .replace('zone_output = { ur = 1, kuka = 18, abb = "doCnvBeltZone" }', "zone_output = { ur = 1 }")
        .replace("timer = { kuka = 1 }", "")
    )
    with pytest.raises(
        GenerateError, match=r"conveyor \(ur, UR10e\): .* the part at .*: (out of reach|the arm would change its conf)"
    ):
        check_envelope(load_cell(path), None)
