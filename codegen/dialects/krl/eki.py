"""KUKA.EthernetKRL's KRL functions (EKI_Init ... EKI_GetReal) and its channels, the network partner a device."""

from __future__ import annotations

import functools
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from types import MappingProxyType

from lark import Tree

from codegen.dialects.core.files import Finding
from codegen.dialects.core.parsing import node_start
from codegen.dialects.core.values import Record, RunError, f32
from codegen.dialects.krl.builtins import STRUCTS, type_name_of

# Sources: KUKA, KST EthernetKRL 2.2 (19.12.2012) as shown by easymanua.ls: the configuration file's structure
# (ETHERNETKRL / CONFIGURATION / EXTERNAL IP, PORT, TYPE / INTERNAL ...; RECEIVE / XML / ELEMENT Tag, Type REAL INT
# BOOL STRING FRAME, Set_Flag; SEND / XML / ELEMENT Tag), per-element data memories read out FIFO, "A message is
# generated for each error ... EKI_STATUS – Structure for function-specific return values" (6.2.7); Roboception's
# rc_visard manual (EKI bridge): the files live in C:\KRC\ROBOTER\Config\User\Common\EthernetKRL and are read when
# the connection is initialised, EKI_Init(name) / EKI_Open(name) / EKI_Close(name), the name the file's without
# .xml. Public KRL programs: RET = EKI_GetReal(channel, "path", variable), RET.Msg_No == 0 where the call worked.
# Not confirmed in the manual's text (marked so in targets/kuka.toml): the EKI_STATUS components besides Msg_No and
# Connected (Buff, Read, Counter: recalled); the message numbers below (secondary sources: KUKA users' reports and
# public programs' notes, not the manual's diagnosis chapter); that an element the configuration does not name
# gives a message of its own (number assumed); that an element of a received document the configuration does not
# name is dropped.
STATUS = STRUCTS["EKI_STATUS"]
SUFFIX = ".xml"  # a channel's configuration file, named as the channel (KRL.configurations)
ERRORS = {
    "ok": 0,
    "not_initialised": 3,  # a function on a channel no EKI_Init made (assumed number)
    "not_connected": 9,  # "Connection not available" (EKI00009: users' reports)
    "empty": 15,  # "Access to empty element memory" (EKI00015: users' reports, a public program's notes)
    "unknown_element": 16,  # an element path the configuration does not name (assumed number)
    "already_initialised": 23,  # "Initialization already performed" (EKI00023: users' reports)
    "no_configuration": 6,  # the configuration file cannot be read or interpreted (assumed number)
}
# EKI_GetInt / EKI_GetReal / EKI_GetBool write their third argument (OUT): the compiler gives it a setter
OUT_PARAMETERS = {"EKI_GETINT": (2,), "EKI_GETREAL": (2,), "EKI_GETBOOL": (2,)}
WRITTEN = OUT_PARAMETERS
GET_TYPES = {"EKI_GETINT": "INT", "EKI_GETREAL": "REAL", "EKI_GETBOOL": "BOOL"}


# EKI_Init of a channel whose configuration file is not there: the option cannot read it, and EKI_Init fails with a
# message (where the controller keeps the file: Roboception's rc_visard manual, EKI bridge; that the function then
# stops the program as EthernetKRL's other errors do: users' reports, the manual's text not seen here)
MISSING = (
    "EKI_Init: the channel's configuration {file} is missing (EthernetKRL reads it from "
    "C:\\KRC\\ROBOTER\\Config\\User\\Common\\EthernetKRL; here it belongs beside the program)"
)


class ConfigError(ValueError):
    """A configuration file the option could not interpret (EKI_Init's message)."""


@dataclass(frozen=True)
class Config:
    """What a channel's XML configuration says: the partner's address, the elements received (path -> type) and
    the elements the program may set and send (paths)."""

    ip: str
    port: int
    receive: MappingProxyType  # read-only: one parsed configuration serves every run of the program
    send: tuple


@functools.lru_cache(maxsize=64)
def parse_config(text: str) -> Config:
    """The configuration file's content (ConfigError: not the option's structure), parsed once per text: every
    run's EKI_Init of a program reads the same file."""
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise ConfigError(f"not XML ({exc})") from None
    if root.tag != "ETHERNETKRL":
        raise ConfigError(f"the root element is <{root.tag}>, not <ETHERNETKRL>")
    external = root.find("CONFIGURATION/EXTERNAL")
    if external is None or external.findtext("IP") is None or external.findtext("PORT") is None:
        raise ConfigError("CONFIGURATION/EXTERNAL has no IP and PORT")
    try:
        port = int(external.findtext("PORT"))
    except ValueError:
        raise ConfigError(f"PORT {external.findtext('PORT')!r} is not a number") from None
    receive = {}
    for element in root.findall("RECEIVE/XML/ELEMENT"):
        tag, kind = element.get("Tag"), element.get("Type")
        if not tag:
            raise ConfigError("a RECEIVE element without Tag")
        if kind is not None:  # without a Type: an element for an event flag only, no memory
            receive[tag] = kind.upper()
    send = tuple(e.get("Tag") for e in root.findall("SEND/XML/ELEMENT") if e.get("Tag"))
    return Config(external.findtext("IP").strip(), port, MappingProxyType(receive), send)


def check_config(text: str, filename: str) -> None:
    """generate's check of a configuration it writes: RunError naming the file where the option could not read it."""
    try:
        parse_config(text)
    except ConfigError as exc:
        raise RunError(f"{filename}: {exc}") from None


def unconfigured(name: str, tree, channels: frozenset) -> list[Finding]:
    """check: each EKI_Init of a channel named by a literal whose configuration file is not among the program's
    files (`channels`: their names without .xml, upper case) stops the program there."""
    out = []
    for sub in tree.iter_subtrees_topdown():
        if sub.data != "call" or str(sub.children[0]).upper() != "EKI_INIT" or len(sub.children) < 2:
            continue
        args = sub.children[1]
        first = args.children[0] if isinstance(args, Tree) and args.children else None
        if not isinstance(first, Tree) or first.data != "string":
            continue
        channel = str(first.children[0]).strip('"')
        if channel.upper() not in channels:
            line, column = node_start(sub)
            out.append(Finding(name, line, column, "error", "missing-file", MISSING.format(file=channel + SUFFIX)))
    return out


def status(buff: int = 0, read: int = 0, msg_no: int = 0, connected: bool = False, counter: int = 0) -> Record:
    return Record("EKI_STATUS", zip([n for n, _t in STATUS], (buff, read, msg_no, connected, counter), strict=True))


READS = {t: f for f, t in GET_TYPES.items()}  # a RECEIVE element's type: the function that reads it


@dataclass
class Channel:
    """One channel as the option keeps it: initialised from its configuration, open (connected) or not, a FIFO
    memory per received element, the values set for sending, a time stamp per document received. The network
    partner at its other end (a device of the run with network_partner) gets it on EKI_Open as its link: it
    hands documents to deliver() and ends the connection with drop()."""

    config: Config
    connected: bool = False
    memories: dict = field(default_factory=dict)  # path -> [value text, ...] (oldest first)
    stamps: dict = field(default_factory=dict)  # path -> [counter, ...]
    staged: dict = field(default_factory=dict)  # path -> value set with EKI_SetInt
    counter: int = 0

    def deliver(self, document: dict) -> None:
        """A document from the partner ({path: text}): each element the configuration names goes to its memory;
        the rest is dropped (assumed: the option keeps only what it is configured for)."""
        if not self.connected:
            return
        self.counter += 1
        for path, value in document.items():
            if path in self.config.receive:
                self.memories.setdefault(path, []).append(value)
                self.stamps.setdefault(path, []).append(self.counter)

    def drop(self) -> None:
        """The partner went off the network: the connection is lost, the memories stay readable."""
        self.connected = False


def _under(path: str, root: str) -> bool:
    return path == root or path.startswith(root + "/")


def _value(text: str, type_name: str, where: str, path: str):
    try:
        if type_name == "INT":
            return int(text)
        if type_name == "REAL":
            return f32(float(text))
        return text.strip().lower() in ("1", "true")
    except ValueError:
        raise RunError(f"{where}: the element {path} holds {text!r}, not a {type_name}") from None


def _partner(m):
    return next((d for d in m.devices if getattr(d, "network_partner", False)), None)


def _init(m, key, name, where, **_kw):
    if key in m.state.channels:
        return status(msg_no=ERRORS["already_initialised"])
    text = getattr(m.program, "eki_configs", {}).get(key)
    if text is None:
        raise RunError(f"{where}: {MISSING.format(file=name + SUFFIX)}")
    try:
        config = parse_config(text)
    except ConfigError as exc:
        raise RunError(f"{where}: EKI_Init: the configuration {name}.xml: {exc}") from None
    m.state.channels = {**m.state.channels, key: Channel(config)}
    return status()


def _open(m, channel: Channel, **_kw):
    partner = _partner(m)
    if partner is None or not partner.connect(m, channel):  # nobody listens at the configured address
        return status(msg_no=ERRORS["not_connected"])
    channel.connected = True
    return status(connected=True)


def _close(m, channel: Channel, **_kw):
    channel.connected = False
    return status()


def _clear(m, channel: Channel, key=None, **_kw):
    channel.connected = False
    m.state.channels = {k: v for k, v in m.state.channels.items() if k != key}
    return status()


def _setint(m, channel: Channel, path=None, value=None, **_kw):
    if path not in channel.config.send:
        return status(msg_no=ERRORS["unknown_element"], connected=channel.connected)
    channel.staged = {**channel.staged, path: value}
    return status(connected=channel.connected)


def _send(m, channel: Channel, path=None, **_kw):
    if not channel.connected:
        return status(msg_no=ERRORS["not_connected"])
    if not any(_under(p, path) for p in channel.config.send):
        return status(msg_no=ERRORS["unknown_element"], connected=True)
    _partner(m).take(m, {p: v for p, v in channel.staged.items() if _under(p, path)})
    return status(connected=True)


def _checkbuffer(m, channel: Channel, path=None, **_kw):
    if path not in channel.config.receive:
        return status(msg_no=ERRORS["unknown_element"], connected=channel.connected)
    return status(buff=len(channel.memories.get(path, ())), connected=channel.connected)


def _clearbuffer(m, channel: Channel, path=None, **_kw):
    for p in channel.memories:
        if _under(p, path):
            channel.memories[p], channel.stamps[p] = [], []
    return status(connected=channel.connected)


def _get(m, channel: Channel, path=None, type_name=None, where="", **_kw):
    configured = channel.config.receive.get(path)
    if configured is None:
        return status(msg_no=ERRORS["unknown_element"], connected=channel.connected), None
    if configured != type_name:
        function = READS.get(configured, "its function")
        raise RunError(f"{where}: the element {path} is configured as {configured}: read it with {function}")
    memory = channel.memories.get(path)
    if not memory:
        return status(msg_no=ERRORS["empty"], connected=channel.connected), None
    text, stamp = memory.pop(0), channel.stamps[path].pop(0)
    value = _value(text, type_name, where, path)
    return status(buff=len(memory), read=1, connected=channel.connected, counter=stamp), value


DONE = {
    "EKI_OPEN": _open,
    "EKI_CLOSE": _close,
    "EKI_CLEAR": _clear,
    "EKI_SETINT": _setint,
    "EKI_SEND": _send,
    "EKI_CHECKBUFFER": _checkbuffer,
    "EKI_CLEARBUFFER": _clearbuffer,
    "EKI_GETINT": _get,
    "EKI_GETREAL": _get,
    "EKI_GETBOOL": _get,
}


def _text(value, where: str, name: str, what: str) -> str:
    if not isinstance(value, str):
        raise RunError(f"{where}: {name}: {what} is a CHAR array, got {type_name_of(value)}")
    return value


def _call(name: str, arity: int, describe: str):
    """A channel function: its arguments checked, then done on the run's channel of that name."""
    key = name.upper()

    def call(fr, args, kwargs, where, setters=None):
        if len(args) != arity:
            raise RunError(f"{where}: {name} takes {arity} arguments ({describe}), got {len(args)}")
        channel_name = _text(args[0], where, name, "the channel")
        path = _text(args[1], where, name, "the element path") if arity > 1 else None
        m = fr.m
        if key == "EKI_INIT":
            return _init(m, channel_name.upper(), channel_name, where)
        channel = m.state.channels.get(channel_name.upper())
        if key in GET_TYPES:
            if setters is None or setters[2] is None:
                raise RunError(f"{where}: {name}: the value (OUT) is a variable")
            if channel is None:
                return status(msg_no=ERRORS["not_initialised"])
            result, value = _get(m, channel, path=path, type_name=GET_TYPES[key], where=where)
            if value is not None:
                setters[2](fr, value)
            return result
        if channel is None:
            return status(msg_no=ERRORS["not_initialised"])
        value = args[2] if arity > 2 else None
        return DONE[key](m, channel, key=channel_name.upper(), path=path, value=value, where=where)

    return call


BUILTINS = {
    "EKI_INIT": _call("EKI_Init", 1, "the channel"),
    "EKI_OPEN": _call("EKI_Open", 1, "the channel"),
    "EKI_CLOSE": _call("EKI_Close", 1, "the channel"),
    "EKI_CLEAR": _call("EKI_Clear", 1, "the channel"),
    "EKI_SETINT": _call("EKI_SetInt", 3, "the channel, the element path, the value"),
    "EKI_SEND": _call("EKI_Send", 2, "the channel, the element path whose structure is sent"),
    "EKI_CHECKBUFFER": _call("EKI_CheckBuffer", 2, "the channel, the element path"),
    "EKI_CLEARBUFFER": _call("EKI_ClearBuffer", 2, "the channel, the element path"),
    "EKI_GETINT": _call("EKI_GetInt", 3, "the channel, the element path, the variable"),
    "EKI_GETREAL": _call("EKI_GetReal", 3, "the channel, the element path, the variable"),
    "EKI_GETBOOL": _call("EKI_GetBool", 3, "the channel, the element path, the variable"),
}
