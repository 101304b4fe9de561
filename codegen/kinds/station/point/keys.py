"""The point mode's part of the cell file: a point station's `mark` and the poses the reading does not move."""

from __future__ import annotations

from codegen.guard import TAUGHT_RANGE_MM
from codegen.model.schema import Key, KindKeys

KEYS = KindKeys(
    reads=("io",),
    station_keys={
        "mark": Key(
            "numbers",
            "where the camera saw the station's mark at calibration: x, y (mm, base frame), theta (deg)",
            count=3,
            required=True,
            low=-TAUGHT_RANGE_MM,
            high=TAUGHT_RANGE_MM,
        ),
        "fixed": Key(
            "list",
            "poses that ride with the robot (a tray on the AGV that carries it): visited as taught, not moved by the "
            "reading; not the work pose",
            values=Key("string", "a pose name"),
            unique=True,
        ),
    },
)
