"""The classes of change verify must catch in every kind's programs: edits of the cell model (a program made from a
perturbed cell, judged against the true one) and edits of a program's text (per controller, kind-independent where
the kinds' programs share a construct), each with the scenarios that reveal it."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from codegen.poses import POSE_FORMATS

ALL = None  # every case of the program


def _tool(cell, tcp2flange: np.ndarray | None = None, mass: float | None = None):
    robot = cell.robot
    tool = robot.tool
    if tcp2flange is not None:
        values = tuple(float(v) + 0.0 for v in POSE_FORMATS[cell.pose_format][2](tcp2flange))
        tool = replace(tool, tcp=values, tcp2flange=tcp2flange)
    if mass is not None:
        tool = replace(tool, mass_kg=mass)
    return replace(cell, robot=replace(robot, tool=tool))


def tool_short(cell):
    shorter = cell.robot.tool.tcp2flange @ np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, -10.0], [0, 0, 0, 1]])
    return _tool(cell, tcp2flange=shorter)


def section(cell, kind: str, **changes):
    return replace(cell, sections={**cell.sections, kind: replace(cell.sections[kind], **changes)})


def motion(cell, **changes):
    return replace(cell, motion=replace(cell.motion, **changes))


def laser(cell, **changes):
    return section(cell, "laser", **changes)


def window_end(cell):
    conveyor = cell.sections["conveyor"]
    start, end = conveyor.pick.window_mm
    return section(cell, "conveyor", pick=replace(conveyor.pick, window_mm=(start, end + 100.0)))


def encoder_swapped(cell):
    conveyor = cell.sections["conveyor"]
    inputs = {t: tuple(reversed(v)) for t, v in conveyor.pick.encoder_inputs.items()}
    return section(cell, "conveyor", pick=replace(conveyor.pick, encoder_inputs=inputs))


def pallets(cell, **changes):
    """Every pallet of the cell changed alike."""
    return replace(
        cell, sections={**cell.sections, "pallet": tuple(replace(p, **changes) for p in cell.sections["pallet"])}
    )


def pallet_timeout(cell, factor: float):
    return replace(
        cell,
        sections={
            **cell.sections,
            "pallet": tuple(
                replace(p, io=replace(p.io, timeout_s=factor * p.io.timeout_s)) for p in cell.sections["pallet"]
            ),
        },
    )


# name -> (what it needs of the cell: "arm", "tool" or a kind's section; the perturbed cell; the scenarios that
# reveal it, ALL: any case)
MODEL = {
    "tool_10mm_short": ("tool", tool_short, ALL),
    "payload_x10": ("tool", lambda c: _tool(c, mass=10 * c.robot.tool.mass_kg), ALL),
    "work_speed_x1_7": ("arm", lambda c: motion(c, work_speed_mm_s=1.7 * c.motion.work_speed_mm_s), ALL),
    "travel_speed_x2": ("arm", lambda c: motion(c, speed_mm_s=2 * c.motion.speed_mm_s), ALL),
    "start_tolerance_30deg": ("arm", lambda c: motion(c, start_tolerance_deg=30.0), frozenset({"start_away"})),
    "window_end_100mm_later": ("conveyor", window_end, ALL),
    "encoder_a_b_swapped": ("conveyor", encoder_swapped, ALL),
    "pallet_box_payload_x2": (
        "pallet",
        lambda c: pallets(c, box_mass_kg=2 * c.sections["pallet"][0].box_mass_kg),
        ALL,
    ),
    "pallet_blends_off": ("pallet", lambda c: pallets(c, zone_mm=0.0), ALL),
    "pallet_way_home_retreat_x2": (
        "pallet",
        lambda c: motion(c, retreat_mm=2 * c.motion.retreat_mm),
        frozenset({"start_away", "start_mid_cycle"}),
    ),
    "pallet_interlock_timeout_x2": ("pallet", lambda c: pallet_timeout(c, 2.0), frozenset({"part_missing"})),
    "search_10x_faster": (
        "laser",
        lambda c: laser(c, search_speed_mm_s=10 * c.sections["laser"].search_speed_mm_s),
        ALL,
    ),
}


def _kuka_last(match) -> str:
    """The laser TCP's distance from the production tool's stored value (TOOL_DATA[3] of the bundled cell)."""
    return (
        "DIST = SQRT("
        + " + ".join(
            f"(LSR_TCP[{i}] - TOOL_DATA[3].{a}) * (LSR_TCP[{i}] - TOOL_DATA[3].{a})"
            for i, a in ((1, "X"), (2, "Y"), (3, "Z"))
        )
        + ")"
    )


def _abb_last(match) -> str:
    """A laser TCP coordinate less the production tool's stored one (tPin of the bundled cell)."""
    return f"(lsr_tcp{{{match.group(1)}}} - tPin.tframe.trans.{'xyz'[int(match.group(1)) - 1]})"


# name -> target -> (pattern, replacement) on the first match in the program's files; where a kind's program has
# no match the class does not apply to it (the matrix test lists that)
TEXT = {
    # a station's first release after the move out of its place: the part dropped on the travel (the next pose)
    "release_moved_to_the_travel": {
        "ur": (r"^(    vis_release\(\)\n)(    movel\([^\n]*\n)", r"\2\1"),
        "kuka": (
            r"^(  IF NOT VIS_RELEASE\(\) THEN\n    RETURN\n  ENDIF\n)"
            r"(  TARGET = [^\n]*\n  \$VEL\.CP = [^\n]*\n  LIN [^\n]*\n)",
            r"\2\1",
        ),
        "abb": (r"^(    vis_release;\n)((?:    Conf\w \\\w+;\n)*    MoveL [^\n]*\n)", r"\2\1"),
        "dtrans": (r"^(  Call vis_release\(\)\n)(  MovL [^\n]*\n)", r"\2\1"),
    },
    "payload_dropped": {
        "ur": (r"^\s*set_target_payload\([^\n]*\n", ""),
        "kuka": (r"^\s*\$LOAD = \w+\n", ""),
    },
    # every load's inertia written as zero (a point mass), in each controller's form (tests/kinds/test_loads_verify.py)
    "inertia_zeroed": {
        "ur": (r"(set_target_payload\([^\n]*\], )\[[^\]]*\]\)", r"\1[0, 0, 0, 0, 0, 0])", 0),
        "kuka": (r"J \{X -?[\d.]+,Y -?[\d.]+,Z -?[\d.]+\}", "J {X 0.0,Y 0.0,Z 0.0}", 0),
        "abb": (r"(\[-?[\d.]+, -?[\d.]+, -?[\d.]+, -?[\d.]+\]), -?[\d.]+, -?[\d.]+, -?[\d.]+\]", r"\1, 0, 0, 0]", 0),
    },
    "gripper_feedback_not_awaited": {
        "ur": (r"while get_standard_digital_in\((\d+)\) != True:", "while False:"),
        "kuka": (r"WHILE \$IN\[(\d+)\] <> TRUE", "WHILE FALSE"),
        "abb": (r"WaitDI (\w+), 1 \\MaxTime:=IO_TIMEOUT;", "WaitTime 0.02;"),
    },
    # a KRL program's stop is its message, acknowledged (the HALT after it is the restart's: a stop's RETURN
    # keeps it from moving on, "return_after_a_stop_removed")
    "stop_removed": {
        "ur": (r"^(\s+)halt\n", ""),
        "abb": (r"^\s+EXIT;\n", ""),
        "dtrans": (r"^(\s+)Halt\n", ""),
    },
    "return_after_a_stop_removed": {  # every one
        "kuka": (r"^(\s+\w+_HALT\(\)\n)\s+RETURN\n", r"\1", 0),
    },
    "start_check_removed": {  # the stop the check calls, a message instead
        "ur": (r'^(\s+)\w+_stop\(("start with the arm at home[^"]*")\)', r"\1textmsg(\2)"),
        "abb": (r'^(\s+)\w+_stop ("start with the arm at home[^"]*");', r"\1TPWrite \2;"),
    },
    "pallet_interlock_not_awaited": {  # the wait for a box at Q (or Q clear), then the stop's message
        "ur": (r'^\s*pal_wait\(\d+, "[^"]*(no box at the pick place|pick place is not clear)[^"]*"\)\n', ""),
        "kuka": (r"^\s*IF NOT PAL_(PART|CLEAR)\(\) THEN\n\s*RETURN\n\s*ENDIF\n", ""),
        "abb": (
            r"WaitDI (diCartonAtQ|diPartAtQ|diQClear), 1 \\MaxTime:=STACK_WAIT \\TimeFlag:=late;",
            "late := FALSE;",
        ),
        "dtrans": (r"^(\s*)If DIn\((3|7)\) <> True Then\n", r"\1If False Then\n"),
    },
    "pallet_carried_payload_dropped": {
        "ur": (r"^\s*set_target_payload\([^\n]*# the tool and the box\n", ""),
        "kuka": (r"^\s*\$LOAD = PAL_LOAD_BOX\n", ""),
        "abb": (r"^\s*GripLoad stack_box;\n", ""),
    },
    "carried_payload_kept_after_release": {
        "ur": (r"^\s*set_target_payload\([^\n]*# the tool alone\n", "", 0),
        "kuka": (r"^ {4,}\$LOAD = (?:PAL_LOAD|LOAD_DATA\[\d+\])\n", "", 0),
        "abb": (r"^\s*GripLoad load0;\n", "", 0),
    },
    "pallet_way_home_skipped": {
        "ur": (r"^(\s*)if pal_away:", r"\1if False:"),
        "kuka": (r"^(\s*)IF AWAY THEN", r"\1IF FALSE THEN"),
        "abb": (r"^\s*MoveL RelTool\(CRobT\(\\Tool:=stack_tool[^\n]*\n", ""),  # the retreat along the tool's z
    },
    "pallet_blend_on_the_place": {
        "ur": (r"(movel\(pal_pose\(x, y, z, a\), a=[\d.]+, v=[\d.]+)\)", r"\1, r=0.001)"),
        "kuka": (r"^(\s+LIN TARGET)\b([^\n]*)\n", r"\1 C_DIS\n"),
        "abb": (r"(MoveL target, stack_work, )fine,", r"\1stack_zone,"),
    },
    "camera_range_check_removed": {
        "ur": (r"if x < CNV_X_MIN or x > CNV_X_MAX or", "if False and x > CNV_X_MAX or"),
        "kuka": (r"IF \(PART_X < CNV_X_MIN\) OR \(PART_X > CNV_X_MAX\) OR", "IF FALSE AND (PART_X > CNV_X_MAX) OR"),
        "abb": (r"IF x < CNV_X_MIN OR x > CNV_X_MAX OR", "IF FALSE AND x > CNV_X_MAX OR"),
    },
    "blend_on_the_grip": {
        "ur": (r"(movel\(cnv_on_part\(x, y, z, 0\), a=[\d.]+, v=[\d.]+)\)", r"\1, r=0.01)"),
        "kuka": (r"^(\s+LIN ON_PART)\b([^\n]*)\n", r"\1 C_DIS\n"),
        "abb": (r"(MoveL down, cnv_work, )fine,", r"\1z10,"),
    },
    "tcp_written_despite_its_range_check": {
        "ur": (r"if sqrt\(off_x \* off_x \+ off_y \* off_y \+ off_z \* off_z\) > LSR_OFFSET_MAX:", "if False:"),
        "kuka": (r"IF DIST > LSR_OFFSET_MAX THEN", "IF FALSE THEN"),
        "abb": (r"IF off > LSR_OFFSET_MAX THEN", "IF FALSE THEN"),
    },
    "tcp_not_written": {
        "ur": (r"^\s*global \w+ = p\[lsr_tcp\[0\][^\n]*\n", ""),
        "kuka": (r"^\s*TOOL_DATA\[\d+\]\.X = LSR_TCP\[1\]\n", ""),
        "abb": (r"^\s*\w+\.tframe\.trans := \[lsr_tcp[^\n]*\n", ""),
    },
    # the production tool not read before the calibration: an installation without it goes unnoticed, the TCP
    # found written into a variable of the program's own, lost with it (the case installation_without_tool)
    "production_tool_not_read_first": {
        "ur": (r"^(\s*lsr_before = )\w+\n", r"\1p[0, 0, 0, 0, 0, 0]\n"),
    },
    # the TCP found written into the program's own data, not into the production tool the cell names
    "tcp_written_into_other_data": {
        "ur": (r"global \w+ = p\[lsr_tcp\[0\]", "global lsr_result = p[lsr_tcp[0]"),
        "kuka": (r"TOOL_DATA\[\d+\]\.([XYZ]) = LSR_TCP", r"LSR_NOMINAL.\1 = LSR_TCP", 0),
        "abb": (r"\w+\.tframe\.trans := \[lsr_tcp", "lsr_guess.tframe.trans := [lsr_tcp"),
    },
    # the range check against the production tool's last value instead of the tool as designed (a tool that bends
    # a little at each calibration drifts without an alarm; the UR program never reads the installation variable)
    "tcp_range_against_the_last_result": {
        "kuka": (r"DIST = SQRT\(D\[1\] \* D\[1\] \+ D\[2\] \* D\[2\] \+ D\[3\] \* D\[3\]\)", _kuka_last),
        "abb": (r"\(lsr_tcp\{(\d)\} - LSR_GUESS_TCP\{\d\}\)", _abb_last, 0),
    },
    # straight from home to above the beams, as before the safe pose (the first joint move to the safe pose)
    "approach_not_through_the_safe_pose": {
        "ur": (r"(movej\(lsr_at\([^,]+, [^,]+, )[^)]+\)", r"\1LSR_CLEAR)"),
        "kuka": (r"PTP LSR_SAFE", "PTP LSR_ABOVE[1]"),
        "abb": (r"MoveJ lsr_at\(LSR_SAFE\)", "MoveJ lsr_at(LSR_ABOVE{1})"),
    },
    # a restart in the station goes home from where the arm stands, not out along the tool's axis first
    "no_way_out_after_a_stop": {
        "ur": (r"^\s*movel\(pose_trans\(LSR_S, p\[lsr_p[^\n]*\n\s*movel\(lsr_at\([^\n]*\n", ""),
        "kuka": (r"^\s*LIN HERE[^\n]*\n\s*LIN LSR_SAFE\n", ""),
        "abb": (r"^\s*MoveL here, [^\n]*\n\s*MoveL lsr_at\(LSR_SAFE\), lsr_work, fine, [^\n]*\n", ""),
    },
    # a start anywhere taken for a stop in the station: out and home from wherever the arm stands
    "start_zone_check_removed": {
        "ur": (r"if sqrt\(lsr_p\[0\][^\n]*:", "if False:"),
        "kuka": (r"IF \(SQRT\(HERE[^\n]*THEN", "IF FALSE THEN"),
        "abb": (r"IF Sqrt\(here\.trans\.x[^\n]*\n[^\n]*THEN", "IF FALSE THEN"),
    },
    # a blend where the program measures: the circle's start, where the interrupts go on
    "blend_where_it_measures": {
        "ur": (r"(movel\(lsr_at\([^)]*\), a=[\d.]+, v=LSR_V_WORK)\)(\n\s*lsr_nx = 0)", r"\1, r=0.005)\2"),
        "kuka": (r"(LIN LSR_START\[K\])\n", r"\1 C_DIS\n"),
        "abb": (r"(MoveL lsr_at\(LSR_START\{k\}\), lsr_work, )fine", r"\1z5"),
    },
    # an exact stop on a travel move (above the start on the way in)
    "travel_not_blended": {
        "ur": (r"(movel\(lsr_at\([^)]*\), a=[\d.]+, v=LSR_V_WORK), r=[\d.]+\)", r"\1)"),
        "kuka": (r"(LIN LSR_ABOVE\[1\]) C_DIS", r"\1"),
        "abb": (r"(MoveL lsr_at\(LSR_ABOVE\{1\}\), lsr_work, )lsr_zone", r"\1fine"),
    },
}
