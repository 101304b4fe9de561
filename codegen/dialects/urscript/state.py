"""What a URScript run keeps beside the program's variables (Machine.state)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from codegen.dialects.core.runstate import RunState


@dataclass
class URScriptState(RunState):
    threads: Any = None  # the run's threads.Scheduler, once a thread runs
    speed: Any = None  # the speedl / speedj under way (motion.SpeedMode), None: none
    tcp: tuple | None = None  # set_tcp's pose (m, rotation vector rad), None: the program sets none
    payload: tuple | None = None  # Load.flat() as set_payload / set_target_payload left it
    encoders: dict = field(default_factory=dict)  # encoder index -> (decoder, input A, input B), None: disabled
    settings: dict = field(default_factory=dict)  # an installation setting's name -> (args, kwargs) last given
    flags: dict = field(default_factory=dict)  # flag number -> set_flag's value
