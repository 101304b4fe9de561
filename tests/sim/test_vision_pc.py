"""The simulated vision PC as a device of Program.run: the handshake, its timing and its faults."""

import math

import pytest

from codegen.dialects.core.values import RunError
from codegen.dialects.dtrans.interpreter import load
from codegen.dialects.krl.interpreter import load as load_krl
from codegen.model.vision import PHOTO, POLL_S, PROMPT_S, READ
from codegen.sim.vision_pc import VisionPC

NAMES = {
    "request": "vis_req",
    "command": "vis_cmd",
    "ack": "vis_ack",
    "u": "vis_u",
    "v": "vis_v",
    "angle": "vis_angle",
    "station": "weizhi",
    "x": "mx",
    "y": "my",
    "theta": "mt",
}
DECLS = (
    "Int vis_cmd = 0\nInt vis_req = 0\nInt vis_ack = 0\nDouble vis_u\nDouble vis_v\nDouble vis_angle\n"
    "Int weizhi = 0\nDouble mx = 0.0\nDouble my = 0.0\nDouble mt = 0.0\nInt polls = 0\n"
)
MOVE = "MovJ Trans(1.0, 2.0, 3.0, 0.0, 0.0, 0.0)\n"
# the generated programs' request: a command, a new sequence number, a poll loop with a timeout of 1 s
ASK = (
    "vis_cmd = {command}\nvis_req = vis_ack + 1\n"
    "While vis_ack <> vis_req\n"
    '  If polls >= 20 Then\n    TPWrite 0, "no answer"\n    Halt\n  EndIf\n'
    "  Sleep 0.05\n  polls = polls + 1\nEndWhile\n"
)
SHOW = 'TPWrite 0, "%d %g %g %g %d", weizhi, mx, my, mt, vis_ack\n'
ANSWER = {"weizhi": 3, "mx": 612.5, "my": -280.0, "mt": 2.5}


class FixedCamera:
    def __init__(self) -> None:
        self.poses = []

    def photo(self, tcp2base):
        self.poses.append(tcp2base)
        return 1.5, 2.5, -3.5


def _run(text, **vision):
    return load(DECLS + text, "t.prg").run({}, devices=[VisionPC(NAMES, **vision)])


def test_a_read_is_answered_with_the_station_and_mark_after_its_latency():
    trace = _run(MOVE + ASK.format(command=READ) + SHOW, answer=ANSWER)
    assert trace.messages == ["3 612.5 -280 2.5 1"]
    assert not trace.halted


def test_a_photo_request_is_answered_from_the_last_pose():
    camera = FixedCamera()
    trace = _run(MOVE + ASK.format(command=PHOTO) + 'TPWrite 0, "%g %g %g", vis_u, vis_v, vis_angle\n', camera=camera)
    assert trace.messages == ["1.5 2.5 -3.5"]
    assert len(camera.poses) == 1 and camera.poses[0][0, 3] == pytest.approx(1.0)


@pytest.mark.parametrize("behaviour", ["never", "stale", "other_sequence", "too_late"])
def test_an_unanswered_request_ends_in_the_timeout(behaviour):
    trace = _run(MOVE + ASK.format(command=READ) + SHOW, answer=ANSWER, behaviour=behaviour, latency_s=1.5)
    assert trace.halted and trace.halt_message == "no answer"


@pytest.mark.parametrize(("behaviour", "latency"), [("prompt", PROMPT_S), ("late", 0.8), ("twice", 0.2)])
def test_an_answer_within_the_timeout_is_used(behaviour, latency):
    trace = _run(MOVE + ASK.format(command=READ) + SHOW, answer=ANSWER, behaviour=behaviour, latency_s=latency)
    assert trace.messages == ["3 612.5 -280 2.5 1"]


def test_the_second_answer_comes_later_and_changes_what_a_later_read_sees():
    """Answered twice: a program that reads the variables again after another wait sees the second look."""
    text = MOVE + ASK.format(command=READ) + SHOW + "Sleep 1.0\n" + SHOW
    trace = _run(text, answer=ANSWER, behaviour="twice", latency_s=0.2)  # both answers two polls apart
    assert trace.messages == ["3 612.5 -280 2.5 1", "3 613 -279.5 2.5 1"]


def test_the_clock_runs_to_the_answer():
    """A wait without a limit ends when the answer is due: latency 0.3 s, polled every 0.05 s."""
    text = MOVE + "vis_cmd = 1\nvis_req = vis_ack + 1\nWaitUntil vis_ack == vis_req\n" + SHOW
    program = load(DECLS + text, "t.prg")
    trace = program.run({}, devices=[VisionPC(NAMES, answer=ANSWER, latency_s=0.3)])
    assert trace.messages == ["3 612.5 -280 2.5 1"]
    with pytest.raises(RunError, match=r"^t.prg:15:1: WaitUntil a condition that nothing here makes true"):
        program.run({}, devices=[VisionPC(NAMES, answer=ANSWER, behaviour="never")])


def test_a_request_while_the_arm_moves_is_an_error():
    """KRL's advance run: without a wait for the arm, the request runs while the PTP is still moving."""
    dat = "DEFDAT T PUBLIC\nDECL INT VIS_CMD=0\nDECL INT VIS_REQ=0\nDECL INT VIS_ACK=0\n"
    dat += "DECL INT VIS_STATION=0\nENDDAT\n"
    body = "PTP {X 100.0,Y 0.0,Z 300.0,A 0.0,B 90.0,C 0.0}\nPTP {X 400.0,Y 0.0,Z 300.0,A 0.0,B 90.0,C 0.0}\n{stop}"
    body += "VIS_CMD = 1\nVIS_REQ = VIS_ACK + 1\nWAIT FOR VIS_ACK == VIS_REQ\n"
    names = {"request": "VIS_REQ", "command": "VIS_CMD", "ack": "VIS_ACK", "station": "VIS_STATION"}
    for stop, fails in (("", True), ("WAIT SEC 0\n", False)):
        src = "DEF T()\n" + body.replace("{stop}", stop) + "END\n"
        program = load_krl(src, "t.src", dat)
        devices = [VisionPC(names, answer={"VIS_STATION": 2})]
        if fails:
            with pytest.raises(RunError, match=r"^t.src:6:1: photo requested while the arm moves .*move at line 3"):
                program.run({}, devices=devices)
        else:
            assert not program.run({}, devices=devices).halted


@pytest.mark.parametrize(
    ("text", "camera", "message"),
    [
        (MOVE + ASK.format(command=PHOTO), None, r"^t.prg:20:3: the program waits for a photo and no camera"),
        (ASK.format(command=PHOTO), FixedCamera(), r"^t.prg:19:3: a photo was requested before the robot moved"),
        (MOVE + ASK.format(command=7), FixedCamera(), r"^t.prg:20:3: the vision PC got command 7: neither 1 .* nor 2"),
    ],
)
def test_handshake_errors(text, camera, message):
    with pytest.raises(RunError, match=message):
        _run(text, camera=camera)


def test_an_undeclared_answer_variable_is_named():
    text = (DECLS + MOVE + ASK.format(command=PHOTO)).replace("Double vis_v\n", "")
    with pytest.raises(RunError, match=r"^t.prg: the vision interface variable vis_v is not declared$"):
        load(text, "t.prg").run({}, devices=[VisionPC(NAMES, camera=FixedCamera())])


def test_without_names_the_vision_pc_does_nothing():
    trace = load(DECLS + MOVE + ASK.format(command=READ), "t.prg").run({}, devices=[VisionPC(None)])
    assert trace.halted and trace.halt_message == "no answer"
    assert math.isclose(20 * POLL_S, 1.0)
