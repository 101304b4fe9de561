"""The simulated vision PC as a device of Program.run: the photo handshake through the program's variables."""

import pytest

from codegen.dialects.core.values import RunError
from codegen.dialects.dtrans.interpreter import load
from codegen.kinds.frame.vision_pc import VisionPC

NAMES = {"request": "vis_req", "ack": "vis_ack", "u": "vis_u", "v": "vis_v", "angle": "vis_angle"}
HANDSHAKE = "Int vis_req = 0\nInt vis_ack = 0\nDouble vis_u\nDouble vis_v\nDouble vis_angle\n"
MOVE = "MovJ Trans(1.0, 2.0, 3.0, 0.0, 0.0, 0.0)\n"
PHOTO = 'vis_req = 7\nWaitUntil vis_ack == vis_req\nTPWrite 0, "%g %g %g %d", vis_u, vis_v, vis_angle, vis_ack\n'


class FixedCamera:
    def __init__(self) -> None:
        self.poses = []

    def photo(self, tcp2base):
        self.poses.append(tcp2base)
        return 1.5, 2.5, -3.5


def test_a_photo_request_is_answered_from_the_last_pose():
    camera = FixedCamera()
    trace = load(HANDSHAKE + MOVE + PHOTO, "t.prg").run({}, devices=[VisionPC(NAMES, camera)])
    assert trace.messages == ["1.5 2.5 -3.5 7"]
    assert len(camera.poses) == 1 and camera.poses[0][0, 3] == pytest.approx(1.0)


def test_without_names_the_vision_pc_does_nothing():
    with pytest.raises(RunError, match="WaitUntil a condition that nothing here can make true"):
        load(HANDSHAKE + MOVE + PHOTO, "t.prg").run({}, devices=[VisionPC(None, FixedCamera())])


@pytest.mark.parametrize(
    ("text", "camera", "message"),
    [
        (HANDSHAKE + MOVE + PHOTO, None, r"^t.prg:8:1: the program waits for a photo and no camera is attached"),
        (HANDSHAKE + PHOTO, FixedCamera(), r"^t.prg:7:1: a photo was requested before the robot moved"),
        (
            HANDSHAKE.replace("Double vis_v\n", "") + MOVE + PHOTO,
            FixedCamera(),
            r"^t.prg: the photo interface variable vis_v is not declared$",
        ),
    ],
)
def test_handshake_errors(text, camera, message):
    with pytest.raises(RunError, match=message):
        load(text, "t.prg").run({}, devices=[VisionPC(NAMES, camera)])
