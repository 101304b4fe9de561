"""Source 003's automatic tool calibration as a program kind: the [laser] station and its TCP program."""

from __future__ import annotations

from codegen.protocol import Kind

KIND = Kind(
    "laser",
    order=40,
    target_keys={
        "files": list,  # source 003's automatic TCP program: file patterns with {laser}
        "frame_files": list,  # the setup program that measures the sensor frame with a reference pin: with {frame}
        "names": dict,  # that program's globals verify reads (edges, hits, centres, axis, tcp)
        "production_tool": dict,  # the production tool the TCP found goes into: form, name, fields, unit
        "joint_zone": bool,  # the program blends into and out of its joint moves (the safe pose)
        "circle_blend_mm": float,  # the first half circle blends into the second by this much (0: it stops)
        "entry_routine": bool,  # the program is a routine of the production task, not a program with its own main
        "saved": dict,  # the production tool's module saved after the write: its file (path) and its value there (kept)
        "confirm": bool,  # the operator confirms the production tool's change (old and new X, Y, Z shown, Yes/No)
        "asks_within_s": float,  # the operator's time to answer the confirmation (absent: the program waits)
    },
    section="codegen.kinds.laser.cellfile:SectionPart",
    writer="codegen.kinds.laser.writer:WriterPart",
    derivation="codegen.kinds.laser.derivation:DerivationPart",
    verify="codegen.kinds.laser.plan:VerifyPart",
    scene="codegen.kinds.laser.scene:ScenePart",
    commands="codegen.kinds.laser.commands:CommandsPart",
)
