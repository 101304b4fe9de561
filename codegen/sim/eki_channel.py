"""A KUKA.EthernetKRL channel and the vision PC at its other end: the device behind codegen/dialects/krl/eki.py."""

from __future__ import annotations

from dataclasses import dataclass, field

from codegen.dialects.core.machine import Machine
from codegen.dialects.core.values import RunError, f32
from codegen.dialects.krl.eki import ERRORS, Config, ConfigError, parse_config, status
from codegen.model.vision import PHOTO, READ
from codegen.sim.vision_pc import VisionPC

# The types an element of the configuration's RECEIVE part may have that the functions here read (KST EthernetKRL
# 2.2, XML structure for data reception: STRING, REAL, INT, BOOL, FRAME) and the function that reads each
READS = {"INT": "EKI_GETINT", "REAL": "EKI_GETREAL", "BOOL": "EKI_GETBOOL"}
READ_VALUES = ("station", "x", "y", "theta")  # the answer to a read: the station and the mark, in this order


@dataclass
class Channel:
    """One channel as the option keeps it: initialised from its configuration, open (connected) or not, a FIFO
    memory per received element, the values set for sending, a time stamp per document received."""

    config: Config
    connected: bool = False
    memories: dict = field(default_factory=dict)  # path -> [value text, ...] (oldest first)
    stamps: dict = field(default_factory=dict)  # path -> [counter, ...]
    staged: dict = field(default_factory=dict)  # path -> value set with EKI_SetInt
    counter: int = 0
    opened: bool = False  # EKI_Open was called (and the channel not closed since)

    def take(self, path: str) -> tuple[str, int] | None:
        memory = self.memories.get(path)
        if not memory:
            return None
        return memory.pop(0), self.stamps[path].pop(0)

    def receive(self, document: dict) -> None:
        """A document from the partner: each element the configuration names goes to its memory; the rest is
        dropped (assumed: the option keeps only what it is configured for)."""
        if not self.connected:
            return
        self.counter += 1
        for path, value in document.items():
            if path in self.config.receive:
                self.memories.setdefault(path, []).append(value)
                self.stamps.setdefault(path, []).append(self.counter)


def _text(value) -> str:
    if isinstance(value, bool):
        return "1" if value else "0"
    return repr(float(value)) if isinstance(value, float) else str(value)


def _value(text: str, type_name: str, where: str, path: str):
    try:
        if type_name == "INT":
            return int(text)
        if type_name == "REAL":
            return f32(float(text))
        return text.strip().lower() in ("1", "true")
    except ValueError:
        raise RunError(f"{where}: the element {path} holds {text!r}, not a {type_name}") from None


@dataclass
class EkiVisionPC(VisionPC):
    """The vision PC at the far end of an Ethernet KRL channel: it reads the program's request from the document
    the program sends (its command and request number), and answers with one document holding the request's
    number and every value of the answer, at the element paths the target's facts give ([program] channel).

    Behaviours beyond the variables' (codegen.model.vision): "dropped" closes the connection when the request
    arrives (nothing answers); "incomplete" answers without the answer's last value."""

    channel_facts: dict = field(default_factory=dict)
    channels: dict = field(default_factory=dict)  # name -> Channel (EKI_Init made it)
    _sent: list = field(default_factory=list)  # (command, request) documents received from the program
    _last_command: object = None
    silent = ("never", "stale")

    def attach(self, facts: dict) -> None:
        self.channel_facts = facts

    # --- the transport ------------------------------------------------------------------------------------
    def _request(self, machine: Machine):
        if not self._sent:
            return None
        command, request = self._sent.pop(0)
        self._last_command = command
        return request

    def _command(self, machine: Machine):
        return self._last_command

    def _deliver(self, machine: Machine, ack, values: dict) -> None:
        paths = self.channel_facts["receive"]
        if "station" in values:  # a read's answer holds the mark always: 0 where the station's mode reads none
            values = {**dict.fromkeys(READ_VALUES, 0.0), **values}
        command = READ if "station" in values else PHOTO  # the command answered, said in the answer
        document = {paths["ack"]: _text(ack), paths["command"]: _text(command)}
        named = [(paths[name], _text(value)) for name, value in values.items() if name in paths]
        if self.behaviour == "incomplete" and named:
            named = named[:-1]
        document.update(named)
        for channel in self.channels.values():
            channel.receive(document)

    def _plan(self, machine: Machine, request, where: str) -> None:
        if self.behaviour == "dropped":  # the vision PC goes off the network as the request arrives
            for channel in self.channels.values():
                channel.connected = False
            return
        super()._plan(machine, request, where)

    # --- the option's functions (codegen/dialects/krl/eki.py) ------------------------------------------------
    def eki_channel(self, machine: Machine, function: str, name: str, where: str, **kw):
        key = name.upper()
        if function == "EKI_INIT":
            return self._init(key, kw.get("config"), name, where)
        channel = self.channels.get(key)
        if channel is None:
            return self._failed(function, "not_initialised")
        return getattr(self, "_" + function[4:].lower())(channel, key, where, **kw)

    def _failed(self, function: str, error: str, connected: bool = False):
        result = status(msg_no=ERRORS[error], connected=connected)
        return (result, None) if function in ("EKI_GETINT", "EKI_GETREAL", "EKI_GETBOOL") else result

    def _init(self, key: str, text: str | None, name: str, where: str):
        if key in self.channels:
            return status(msg_no=ERRORS["already_initialised"])
        if text is None:
            raise RunError(f"{where}: EKI_Init: no configuration {name}.xml beside the program (the option reads it)")
        try:
            config = parse_config(text)
        except ConfigError as exc:
            raise RunError(f"{where}: EKI_Init: the configuration {name}.xml: {exc}") from None
        self.channels[key] = Channel(config)
        return status()

    def _open(self, channel: Channel, key: str, where: str, **_kw):
        channel.connected = channel.opened = True
        return status(connected=True)

    def _close(self, channel: Channel, key: str, where: str, **_kw):
        channel.connected = channel.opened = False
        return status()

    def _clear(self, channel: Channel, key: str, where: str, **_kw):
        del self.channels[key]
        return status()

    def _setint(self, channel: Channel, key: str, where: str, path=None, value=None, **_kw):
        if path not in channel.config.send:
            return status(msg_no=ERRORS["unknown_element"], connected=channel.connected)
        channel.staged[path] = value
        return status(connected=channel.connected)

    def _send(self, channel: Channel, key: str, where: str, path=None, **_kw):
        if not channel.connected:
            return status(msg_no=ERRORS["not_connected"])
        if not any(p == path or p.startswith(path + "/") for p in channel.config.send):
            return status(msg_no=ERRORS["unknown_element"], connected=True)
        sent = {p: v for p, v in channel.staged.items() if p == path or p.startswith(path + "/")}
        paths = self.channel_facts["send"]
        if paths["command"] in sent and paths["request"] in sent:
            self._sent.append((sent[paths["command"]], sent[paths["request"]]))
        return status(connected=True)

    def _checkbuffer(self, channel: Channel, key: str, where: str, path=None, **_kw):
        if path not in channel.config.receive:
            return status(msg_no=ERRORS["unknown_element"], connected=channel.connected)
        return status(buff=len(channel.memories.get(path, ())), connected=channel.connected)

    def _clearbuffer(self, channel: Channel, key: str, where: str, path=None, **_kw):
        for p in channel.memories:
            if p == path or p.startswith(path + "/"):
                channel.memories[p], channel.stamps[p] = [], []
        return status(connected=channel.connected)

    def _get(self, channel: Channel, where: str, path: str, type_name: str):
        configured = channel.config.receive.get(path)
        if configured is None:
            return status(msg_no=ERRORS["unknown_element"], connected=channel.connected), None
        if configured != type_name:
            function = READS.get(configured, "its function")
            raise RunError(f"{where}: the element {path} is configured as {configured}: read it with {function}")
        taken = channel.take(path)
        if taken is None:
            return status(msg_no=ERRORS["empty"], connected=channel.connected), None
        text, stamp = taken
        left = len(channel.memories[path])
        value = _value(text, type_name, where, path)
        return status(buff=left, read=1, connected=channel.connected, counter=stamp), value

    def _getint(self, channel: Channel, key: str, where: str, path=None, type_name=None, **_kw):
        return self._get(channel, where, path, type_name)

    _getreal = _getbool = _getint


PARTNER = EkiVisionPC  # codegen.sim.vision_pc.CHANNELS
