"""Careless edits of the checked-in programs of every example cell, per target: verify must fail each.

Each row is a kind of edit a person or a generator bug could make, written as a regular expression
per target (the first match is changed). A target without a row for a kind has no such construct;
docs/kinds/point.md lists those and why. Speed, acceleration, zone and base edits are the motion mutations
of tests/kinds/station_base.py; extra dispatch ids and halts the program goes on from are tested there too.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from support import stations

from codegen.controllers import get_target
from codegen.model.cell import load_cell

REPO = Path(__file__).resolve().parents[2]
CELLS = sorted((REPO / "codegen" / "examples").glob("*.toml"))  # the cells of stations


def _bump(match: re.Match, by: float) -> str:
    return f"{match.group(1)}{float(match.group(2)) + by:.6f}"


NO_ANSWER = "no answer from the vision PC (5 s per request)"  # the vision timeout's stop, in every program
# kind -> target -> (pattern, replacement); the replacement may be a function of the match.
TABLE = {
    "joint_move_made_linear": {
        "ur": (r"^(\s+)movej\(", r"\1movel("),
        "kuka": (r"^(\s+)PTP ", r"\1LIN "),
        "abb": (r"^(\s+)MoveJ ", r"\1MoveL "),
        "dtrans": (r"^(\s*)MovJ ", r"\1MovL "),
    },
    "move_dropped": {
        "ur": (r"^\s+movel\([^\n]*\n", ""),
        "kuka": (r"^\s+LIN [^\n]*\n", ""),
        "abb": (r"^\s+MoveL [^\n]*\n", ""),
        "dtrans": (r"^\s*MovL [^\n]*\n", ""),
    },
    "moves_reordered": {
        "ur": (r"^(\s+movej\([^\n]*\n)(\s+movel\([^\n]*\n)", r"\2\1"),
        "kuka": (
            r"^(\s+TARGET\w* = [^\n]*\n\s+PTP [^\n]*\n)(\s+TARGET = [^\n]*\n\s+\$VEL\.CP = [^\n]*\n\s+LIN [^\n]*\n)",
            r"\2\1",
        ),
        "abb": (  # the configuration-check lines go with their move
            r"^(\s+MoveJ vis_apply[^\n]*\n(?:\s+ConfJ \\On;\n)?)((?:\s+ConfL \\Off;\n)?\s+MoveL [^\n]*\n)",
            r"\2\1",
        ),
        "dtrans": (r"^(\s*MovJ vis_apply[^\n]*\n)(\s*MovL [^\n]*\n)", r"\2\1"),
    },
    "pose_operator_changed": {
        "ur": (r"pose_trans\(corr, ", "pose_add(corr, "),
        "kuka": (r"TARGET = CORR : (\w+)", r"TARGET = \1 : CORR"),
        "abb": (r"PoseMult\(corr, (\[taught\.trans, taught\.rot\])\)", r"PoseMult(\1, corr)"),
    },
    "shift_limit_10_percent_wider": {
        "ur": (r"(MAX_SHIFT_SQ = )([\d.]+)", lambda m: f"{m.group(1)}{float(m.group(2)) * 1.21:.6f}"),
        "kuka": (r"(MAX_SHIFT_SQ=)([\d.]+)", lambda m: f"{m.group(1)}{float(m.group(2)) * 1.21:.6f}"),
        "abb": (r"(MAX_SHIFT_SQ := )([\d.]+)", lambda m: f"{m.group(1)}{float(m.group(2)) * 1.21:.6f}"),
        "dtrans": (r"(MAX_SHIFT_SQ = )([\d.]+)", lambda m: f"{m.group(1)}{float(m.group(2)) * 1.21:.6f}"),
    },
    "taught_digit_plus_0_01_mm": {
        "ur": (r"(p\d+_\w+ = p\[)(-?[\d.]+)", lambda m: _bump(m, 0.00001)),
        "kuka": (r"(DECL (?:E6)?POS P\d+_\w+=\{X )(-?[\d.]+)", lambda m: _bump(m, 0.01)),
        "abb": (r"(CONST robtarget p\d+_\w+ := \[\[)(-?[\d.]+)", lambda m: _bump(m, 0.01)),
        "dtrans": (r"(Point p\d+_\w+ = Trans\()(-?[\d.]+)", lambda m: _bump(m, 0.01)),
    },
    "halt_removed": {
        "ur": (r"^\s+halt\n", ""),
        "kuka": (r"^\s+VIS_HALT\(\)\n", ""),
        "abb": (r"^\s+EXIT;\n", ""),
        "dtrans": (r"^\s*Halt\n", ""),
    },
    "halt_message_of_another_stop": {  # a stop's text changed alone is an edit; into another stop's, its cause is lost
        "ur": (r'vis_stop\("station [^"]*"', f'vis_stop("{NO_ANSWER}"'),
        "kuka": (r'MSG_TXT\[\] = "station [^"]*"', f'MSG_TXT[] = "{NO_ANSWER}"'),
        "abb": (r'vis_stop "station [^"]*"', f'vis_stop "{NO_ANSWER}"'),
        "dtrans": (r'TPWrite 0, "station [^"]*"', f'TPWrite 0, "{NO_ANSWER}"'),
    },
    "mark_x_and_y_swapped": {
        "ur": (r"(m\d+_\w+ = \[)(-?[\d.]+), (-?[\d.]+)", r"\1\3, \2"),
        "kuka": (r"(DECL FRAME M\d+_\w+=\{X )(-?[\d.]+),Y (-?[\d.]+)", r"\1\3,Y \2"),
        "abb": (r"(CONST num m\d+_\w+\{3\} := \[)(-?[\d.]+), (-?[\d.]+)", r"\1\3, \2"),
        "dtrans": (r"(Double m\d+_\w+\[3\] = \{)(-?[\d.]+), (-?[\d.]+)", r"\1\3, \2"),
    },
    "log_line_dropped": {
        "ur": (r"^\s+vis_log\([^\n]*\n", ""),
        "kuka": (r"^\s+VIS_LOG\([^\n]*\n", ""),
        "abb": (r"^\s+vis_log [^\n]*\n", ""),
        "dtrans": (r"^\s*Call vis_log\([^\n]*\n", ""),
    },
    "tool_changed": {
        "abb": (r"(MoveL vis_apply\([^\n]*), vis_tool;", r"\1, tool0;"),
    },
    "index_base_off_by_one": {
        "ur": (r"vis_x - mark\[0\]", "vis_x - mark[1]"),
        "abb": (r"vis_x - mark\{1\}", "vis_x - mark{2}"),
        "dtrans": (r"vis_mark\[0\] - mark\[0\]", "vis_mark[0] - mark[1]"),
    },
    "units_degrees_as_radians": {
        "ur": (r"phi = d2r\(", "phi = ("),
    },
}
ROWS = [(kind, target) for kind, per_target in TABLE.items() for target in per_target]


@pytest.fixture(scope="module")
def checked_in():
    """Each example cell, its cases, and each target's checked-in program (with its companions)."""
    out = {}
    for path in CELLS:
        cell = load_cell(path)
        cases = stations.build_cases(cell, 6, 11)
        for target in cell.targets:
            folder = REPO / "generated" / path.stem / target
            suffixes = get_target(target).suffixes
            text = (folder / f"{path.stem}{suffixes[0]}").read_text(encoding="utf-8")
            data = folder / f"{path.stem}{suffixes[1] if len(suffixes) > 1 else suffixes[0]}"  # its data list
            dat = data.read_text(encoding="utf-8") if len(set(suffixes)) > 1 and data.is_file() else None
            out[path.stem, target] = (cell, cases, (text, dat))
    return out


@pytest.mark.parametrize("cell_name", [p.stem for p in CELLS])
@pytest.mark.parametrize(("kind", "target"), ROWS)
def test_verify_fails_the_edit(checked_in, cell_name, kind, target):
    cell, cases, (text, dat) = checked_in[cell_name, target]
    pattern, replacement = TABLE[kind][target]
    text, count = re.subn(pattern, replacement, text, count=1, flags=re.MULTILINE)
    if count == 0 and dat is not None:  # the data list holds the constants and poses of KRL
        dat, count = re.subn(pattern, replacement, dat, count=1, flags=re.MULTILINE)
    assert count == 1, f"{kind}: nothing to edit in {cell_name}'s {target} program"
    report = stations.verify(cell, stations.source(cell, target, text, dat, kind), cases, first=True)
    assert report.mismatches > 0, f"verify missed {kind} in {cell_name}'s {target} program"


# The vision handshake (codegen/model/vision.py) on the thermometer bench: the order of request, wait and
# read, the new request number, the timeout and (KRL) the wait for the arm before the request.
HANDSHAKE = {
    "reading_taken_before_the_photo": {
        "ur": (r"^(\s+vis_ask\(2\)\n)((?:\s+\w+ = read_input_float_register\(\d+\)\n){3})", r"\2\1"),
        "kuka": (r"^(\s+IF NOT VIS_ASK\(2\) THEN\n\s+RETURN\n\s+ENDIF\n)((?:\s+\w+ = VIS_\w+\n){3})", r"\2\1"),
        "abb": (r"^(\s+vis_ask 2;\n)((?:\s+\w+ := vis_\w+;\n){3})", r"\2\1"),
        "dtrans": (r"^(\s+Call vis_ask\(2\)\n)((?:\s+\w+ = vis_\w+\n){3})", r"\2\1"),
    },
    "request_not_sent": {  # the program waits for an answer to the previous request: it is there already
        "ur": (r"^\s+write_output_integer_register\(\d+, request\)\n", ""),
        "kuka": (r"^\s+VIS_REQ = VIS_REQ \+ 1\n", ""),
        "abb": (r"^\s+vis_req := vis_req \+ 1;\n", ""),
        "dtrans": (r"^\s+vis_req = vis_req \+ 1\n", ""),
    },
    "request_number_from_the_ack": {  # a late answer to the previous cycle's last request counts
        "ur": (r"^(\s+)request = read_output_integer_register\((\d+)\)\n", r"\1request = -1\n"),
        # over its channel KRL numbers requests itself: the answer taken whatever its number
        "kuka": (r"^(\s+)WHILE ACK <> VIS_REQ\n", r"\1WHILE ACK == VIS_REQ - 1\n"),
        "abb": (r"^\s+IF vis_ack > vis_req THEN\n", "    IF TRUE THEN\n"),
        "dtrans": (r"^\s+If vis_ack > vis_req Then\n", "  If True Then\n"),
    },
    "no_timeout": {  # a silent vision PC: the program waits for ever (the step limit ends the run)
        "ur": (r"^(\s+)if polls >= VIS_POLLS:\n", r"\1if False:\n"),
        "kuka": (r"^(\s+)IF POLLS >= VIS_POLLS THEN\n", r"\1IF FALSE THEN\n"),
        "abb": (r" \\MaxTime:=VIS_TIMEOUT;", ";"),
        "dtrans": (r"^(\s+)If polls >= VIS_POLLS Then\n", r"\1If False Then\n"),
    },
    "request_while_the_arm_moves": {
        "kuka": (r"^\s+WAIT SEC 0 ;[^\n]*\n", ""),
    },
}


@pytest.mark.parametrize(("kind", "target"), [(k, t) for k, per in HANDSHAKE.items() for t in per])
def test_verify_fails_a_broken_handshake(checked_in, kind, target):
    cell, cases, (text, dat) = checked_in["thermometer_bench", target]
    pattern, replacement = HANDSHAKE[kind][target]
    text, count = re.subn(pattern, replacement, text, count=1, flags=re.MULTILINE)
    assert count == 1, f"{kind}: nothing to edit in the {target} program"
    report = stations.verify(cell, stations.source(cell, target, text, dat, kind), cases, first=True)
    assert report.mismatches > 0, f"verify missed {kind} in the {target} program"
