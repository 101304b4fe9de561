"""Conveyor tracking (source 002) as a program kind: the [conveyor] table, its calibration, a pick-from-belt program."""

from __future__ import annotations

from codegen.protocol import Kind

KIND = Kind(
    "conveyor",
    order=30,
    target_keys={
        "files": list,  # the pick-from-belt program of a cell with [conveyor.pick]
        "registers": dict,  # the part queue's registers by role (seq, count, x, z, ack, stop)
        "names": dict,  # the same by the names devices and `codegen run --input` use
        "signals": dict,  # the queue as groups of digital signals (ranges of numbered signals, or named signals)
        "encoder_inputs": list,  # the lowest and highest digital input an encoder's A and B may use
        "tracking": list,  # how the pick program follows the belt: "native", "intercept"
        "blends": dict,  # per tracking mode, the moves the program blends into the next (plan.py)
        "unit": str,  # native (ABB): the belt's mechanical unit unless the cell names another
        "units": list,  # native (ABB): the mechanical units a cell may name for its belt
        "unit_signals": dict,  # native (ABB): the tracking option's signals the program uses
        "unit_axis": int,  # native (ABB): the unit's logical axis (7..12: eax_a..eax_f) unless the cell names another
        "drop_settle_s": float,  # native (ABB): the wait after DropWObj before the next WaitWObj
        "timers": int,  # intercept: how many numbered timers ([conveyor.pick] timer gives the program one)
        "timer_s": float,  # intercept: the numbered timers' unit (a time measured is off by up to one)
        "path_acc_m_s2": float,  # the path acceleration the program sets for its straight moves (the descent's ramp)
        "trigger": float,  # native (UR): the frame (s) a thread latches the robot's own encoder at the trigger in
    },
    section="codegen.kinds.conveyor.cellfile:SectionPart",
    writer="codegen.kinds.conveyor.writer:WriterPart",
    verify="codegen.kinds.conveyor.verify:VerifyPart",
    scene="codegen.kinds.conveyor.scene:ScenePart",
    commands="codegen.kinds.conveyor.commands:CommandsPart",
)
