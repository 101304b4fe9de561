"""The vision PC at the far end of a network channel (a target's [program] channel): a device of Program.run."""

from __future__ import annotations

from dataclasses import dataclass, field

from codegen.dialects.core.machine import Machine
from codegen.model.vision import PHOTO, READ
from codegen.sim.vision_pc import VisionPC

READ_VALUES = ("station", "x", "y", "theta")  # the answer to a read: the station and the mark, in this order


def _text(value) -> str:
    """A value as the document's text (XML character data)."""
    if isinstance(value, bool):
        return "1" if value else "0"
    return repr(float(value)) if isinstance(value, float) else str(value)


@dataclass
class ChannelVisionPC(VisionPC):
    """The vision PC as a network partner: the controller's channel connects to it (connect: the channel is its
    link), hands it each document the program sends ({element path: value}; take) and it answers a request with
    one document ({element path: text}) holding the request's number, the command answered and every value of
    the answer, at the element paths of the target's facts ([program] channel receive), through each link.

    Behaviours beyond the variables' (codegen.model.vision): "dropped" ends the connection when the request
    arrives (nothing answers); "incomplete" answers without the last of the answer's values that the channel is
    configured to receive (a value the program reads: one it does not configure would be dropped by the option
    anyway, and the answer would be complete for it)."""

    channel_facts: dict = field(default_factory=dict)
    links: list = field(default_factory=list)  # the channels connected to it (deliver(document), drop())
    _sent: list = field(default_factory=list)  # (command, request) of each request received, not yet planned
    _last_command: object = None
    network_partner = True  # found by the controller's channel functions among the run's devices
    silent = ("never", "stale")

    def attach(self, facts: dict) -> None:
        self.channel_facts = facts

    def connect(self, machine: Machine, link) -> bool:
        """A channel connects: it is listened to from now on."""
        self.links.append(link)
        return True

    def take(self, machine: Machine, document: dict) -> None:
        """A document the program sent: a request where it holds the command and the request's number."""
        paths = self.channel_facts["send"]
        if paths["command"] in document and paths["request"] in document:
            self._sent.append((document[paths["command"]], document[paths["request"]]))

    # --- the transport ------------------------------------------------------------------------------------
    def _request(self, machine: Machine):
        if not self._sent:
            return None
        self._last_command, request = self._sent.pop(0)
        return request

    def _command(self, machine: Machine):
        return self._last_command

    def _deliver(self, machine: Machine, ack, values: dict) -> None:
        paths = self.channel_facts["receive"]
        command = READ if "station" in values else PHOTO  # the command answered, said in the answer
        if command == READ:  # a read's answer holds the mark always: 0 where the station's mode reads none
            values = {**dict.fromkeys(READ_VALUES, 0.0), **values}
        named = [(paths[name], _text(value)) for name, value in values.items() if name in paths]
        head = {paths["ack"]: _text(ack), paths["command"]: _text(command)}
        for link in self.links:
            received = [path for path, _value in named if path in link.config.receive]
            left_out = received[-1:] if self.behaviour == "incomplete" else []
            link.deliver({**head, **{path: value for path, value in named if path not in left_out}})

    def _plan(self, machine: Machine, request, where: str) -> None:
        if self.behaviour == "dropped":  # the vision PC goes off the network as the request arrives
            for link in self.links:
                link.drop()
            return
        super()._plan(machine, request, where)


PARTNER = ChannelVisionPC  # codegen.sim.vision_pc.CHANNELS
