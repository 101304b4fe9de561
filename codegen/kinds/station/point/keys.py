"""The point mode's part of the cell file: a point station's `mark`."""

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
    },
)
