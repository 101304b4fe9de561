"""The simulated vision PC: the other side of the handshake (codegen.model.vision), a device of Program.run."""

from __future__ import annotations

from dataclasses import dataclass, field
from importlib import import_module

from codegen.dialects.core.machine import Machine
from codegen.dialects.core.values import RunError
from codegen.model.vision import PHOTO, PREVIOUS_REQUEST, PROMPT_S, READ, SECOND_LOOK_MM

# the channels a target's program may reach the vision PC through (targets' [program] channel form): the module of
# this package whose PARTNER serves it
CHANNELS = {"eki": "codegen.sim.channel_pc"}
# the behaviours where no answer is written: over variables a vision PC that drops off the network, or has not all
# of an answer, writes nothing (a channel's partner models the connection and the answer's elements itself)
SILENT = ("never", "stale", "dropped", "incomplete")


@dataclass
class VisionPC:
    """The vision PC's side of the handshake, a device of Program.run: when the program waits with a
    request not yet answered, it answers after its latency by its behaviour.

    names: the program's variable or register names, as the target's facts give them: "request",
    "ack", "command", and the answer's "station", "x", "y", "theta" (READ) and "u", "v", "angle"
    (PHOTO); answer: the values of a READ by name (the station id and, for a point station, the mark);
    camera: a SimulatedCamera for PHOTO requests (None: a photo request is an error); previous: the
    previous cycle's READ answer (late_previous sends it late, for the request that cycle gave up on)."""

    names: dict | None
    answer: dict = field(default_factory=dict)
    camera: object = None
    behaviour: str = "prompt"
    latency_s: float = PROMPT_S
    previous: dict = field(default_factory=dict)
    _seen: object = None
    _due: list = field(default_factory=list)  # (time, ack value, values by name)

    _late_sent: bool = False
    silent = SILENT  # the behaviours that answer nothing

    def __post_init__(self) -> None:
        if self.behaviour == "late_previous":
            self._seen = PREVIOUS_REQUEST + 1  # the request the previous cycle gave up on, answered below

    @classmethod
    def for_target(cls, target, answer=None, camera=None, behaviour="prompt", latency_s=PROMPT_S, previous=None):
        """The vision PC a target's program talks to: over the program's variables, or over the channel the
        target's facts name ([program] channel: its form, a module of this package, CHANNELS)."""
        names = target.program.get("photo")
        if names is not None:
            names = {**names, **{k: target.program["inputs"][k] for k in ("station", "x", "y", "theta")}}
        channel = target.program.get("channel")
        kind = cls if channel is None else import_module(CHANNELS[channel["form"]]).PARTNER
        out = kind(names, dict(answer or {}), camera, behaviour, latency_s, dict(previous or {}))
        if channel is not None:
            out.attach(channel)
        return out

    # --- the transport: the program's variables (a channel's partner overrides these) ------------------------
    def _request(self, machine: Machine):
        """The program's request number not yet seen and not answered, or None."""
        request = machine.read_variable(self.names["request"])
        if request is None or request == self._seen or request == machine.read_variable(self.names["ack"]):
            return None
        return request

    def _command(self, machine: Machine):
        return machine.read_variable(self.names["command"])

    def _deliver(self, machine: Machine, ack, values: dict) -> None:
        for name, value in (*values.items(), ("ack", ack)):
            variable = self.names.get(name, name)
            if not machine.write_variable(variable, value):
                raise RunError(f"{machine.program.name}: the vision interface variable {variable} is not declared")

    def next_time(self, machine: Machine) -> float | None:
        if not self._due:
            return None
        return min(t for t, _ack, _values in self._due)

    def on_wait(self, machine: Machine, where: str) -> bool:
        io = self.names
        if not io:
            return False
        if self.behaviour == "late_previous" and not self._late_sent and not machine.moving:
            # the late answer arrives soon after the arm first stands still: after a program that numbers
            # its request from the last answer asked, before the answer to its request (in order)
            self._late_sent = True
            self._due.append((machine.clock + PROMPT_S / 2, PREVIOUS_REQUEST + 1, self._named(self.previous)))
        request = self._request(machine)
        if request is not None:
            self._seen = request
            self._plan(machine, request, where)
        if not self._due:
            return False  # an idle wait: nothing planned
        acted = False
        for item in [d for d in self._due if d[0] <= machine.clock]:
            self._due.remove(item)
            _time, ack, values = item
            self._deliver(machine, ack, values)
            acted = True
        return acted

    def _plan(self, machine: Machine, request, where: str) -> None:
        """A new request: what to answer and when, by the behaviour."""
        if machine.moving:
            line = machine.last_move.line if machine.last_move is not None else "?"
            raise RunError(
                f"{where}: photo requested while the arm moves (the request ran ahead of the move at line {line}: "
                "nothing made the program wait for the arm before it)"
            )
        if self.behaviour in self.silent:
            return
        command = self._command(machine)
        values = self._values(machine, command, where)
        start = machine.clock + self.latency_s
        if self.behaviour == "other_sequence":
            self._due.append((start, request + 1, values))
            return
        self._due.append((start, request, values))
        if self.behaviour == "twice":  # the same request answered again, from a second look
            self._due.append((start + self.latency_s, request, self._values(machine, command, where, again=True)))

    def _values(self, machine: Machine, command, where: str, again: bool = False) -> dict:
        if command == READ:
            if again:  # a second look at a mark: the same place, read a little differently
                return {k: (v + SECOND_LOOK_MM if k in ("x", "y") else v) for k, v in self._named(self.answer).items()}
            return self._named(self.answer)
        if command == PHOTO:
            if self.camera is None:
                raise RunError(
                    f"{where}: the program waits for a photo and no camera is attached "
                    "(codegen verify attaches a simulated one)"
                )
            if machine.last_move is None:
                raise RunError(f"{where}: a photo was requested before the robot moved to a photo pose")
            machine.arm.resolve()
            u, v, angle = self.camera.photo(machine.last_move.tcp2base)
            return {"u": u, "v": v, "angle": angle}
        raise RunError(f"{where}: the vision PC got command {command!r}: neither {READ} (read) nor {PHOTO} (photo)")

    def _named(self, answer: dict) -> dict:
        """A READ answer keyed by the protocol's names (station, x, y, theta) where it names a
        program variable."""
        by_variable = {v: k for k, v in (self.names or {}).items()}
        return {by_variable.get(name, name): value for name, value in answer.items()}
