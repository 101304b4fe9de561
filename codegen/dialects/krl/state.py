"""What a KRL run keeps beside the program's variables (Machine.state)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from codegen.dialects.core.runstate import RunState


@dataclass
class KRLState(RunState):
    # The system variables the program set or read, by name ($BASE, $TOOL, $VEL, $ADVANCE, TOOL_DATA, ...), and
    # the numbers the moves read of them ($VEL.CP, $APO.CDIS, $ACC.CP, VEL_PTP, ACC_PTP: stored alone by
    # `$VEL.CP = x` and BAS): a store by name, as the controller's (sysvars.py reads and writes it)
    sysvars: dict[str, Any] = field(default_factory=dict)
    interrupts: dict = field(default_factory=dict)  # INTERRUPT DECL number -> interrupts.Interrupt
    timers: list | None = None  # $TIMER[n]: (ms at t0, t0 s, stopped) each, once read or set (sysvars.py)
    tool_at_move: np.ndarray | None = None  # the tool (tcp2flange) in force at the last move
    handle: int = 0  # the last message or dialog handle given out
    waiting: dict = field(default_factory=dict)  # handle -> an acknowledgement message still shown
    dialogs: dict = field(default_factory=dict)  # handle -> dialogs.Dialog
    channels: dict = field(default_factory=dict)  # Ethernet KRL channel name -> eki.Channel (EKI_Init made it)
    triggers: tuple = ()  # the TRIGGERs pending for the next motion (trigger.py)
    fresh: dict = field(default_factory=dict)  # id -> (name, value): the numbered data nobody set (motion.py)
    move_bases: dict = field(default_factory=dict)  # id of a MoveEvent -> the $BASE it was planned in (4x4 mm)
