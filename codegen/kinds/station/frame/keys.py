"""The frame mode's part of the cell file: a frame station's keys and [cell.refine]."""

from __future__ import annotations

from codegen.model.schema import Key, KindKeys, Table

REFINE = Table(
    "When a frame station's refinement loop stops (source 001: 0.02 mm and 0.04 deg).",
    {
        "tolerance_mm": Key(
            "number",
            "the frame's shift below which it has converged (at least 0.4 px of the camera's scale)",
            unit="mm",
            low=0.0,
            open_low=True,
            default=0.02,
        ),
        "tolerance_deg": Key(
            "number", "the frame's turn below which it has converged", unit="deg", low=0.0, open_low=True, default=0.04
        ),
        "max_iterations": Key(
            "integer", "photos before the program halts: frame not converged", low=1, high=100, default=10
        ),
    },
)
KEYS = KindKeys(
    reads=("io",),
    cell_tables={"refine": Key("table", REFINE.doc, table=REFINE)},
    station_keys={
        "frame": Key(
            "pose",
            "the calibration frame (the user frame the poses are taught in), base frame",
            count=(6, 7),
            required=True,
        ),
        "photo": Key(
            "pose", "where the arm photographs the mark, in the calibration frame", count=(6, 7), required=True
        ),
        "base_data": Key(
            "integer",
            "the controller's base number the program writes the frame to",
            low=1,
            controllers="those with numbered base data (BASE_DATA[n])",
        ),
    },
)
