"""KUKA.EthernetKRL's KRL functions (EKI_Init ... EKI_GetReal) returning EKI_STATUS, served by a channel device."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass

from codegen.dialects.core.values import Record, RunError
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


class ConfigError(ValueError):
    """A configuration file the option could not interpret (EKI_Init's message)."""


@dataclass(frozen=True)
class Config:
    """What a channel's XML configuration says: the partner's address, the elements received (path -> type) and
    the elements the program may set and send (paths)."""

    ip: str
    port: int
    receive: dict
    send: tuple


def parse_config(text: str) -> Config:
    """The configuration file's content (ConfigError: not the option's structure)."""
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
    return Config(external.findtext("IP").strip(), port, receive, send)


def check_config(text: str, filename: str) -> None:
    """generate's check of a configuration it writes: RunError naming the file where the option could not read it."""
    try:
        parse_config(text)
    except ConfigError as exc:
        raise RunError(f"{filename}: {exc}") from None


def status(buff: int = 0, read: int = 0, msg_no: int = 0, connected: bool = False, counter: int = 0) -> Record:
    return Record("EKI_STATUS", zip([n for n, _t in STATUS], (buff, read, msg_no, connected, counter), strict=True))


def _device(m, where: str, name: str):
    device = next((d for d in m.devices if hasattr(d, "eki_channel")), None)
    if device is None:
        raise RunError(
            f"{where}: {name}: no Ethernet KRL partner is attached to this run (codegen verify attaches one)"
        )
    return device


def _text(value, where: str, name: str, what: str) -> str:
    if not isinstance(value, str):
        raise RunError(f"{where}: {name}: {what} is a CHAR array, got {type_name_of(value)}")
    return value


def _call(name: str, arity: int, describe: str):
    """A channel function: its arguments checked, then done by the channel device (codegen/sim/eki_channel.py)."""

    def call(fr, args, kwargs, where, setters=None):
        if len(args) != arity:
            raise RunError(f"{where}: {name} takes {arity} arguments ({describe}), got {len(args)}")
        channel = _text(args[0], where, name, "the channel")
        path = _text(args[1], where, name, "the element path") if arity > 1 else None
        m = fr.m
        device = _device(m, where, name)
        key = name.upper()
        if key == "EKI_INIT":
            configs = getattr(m.program, "eki_configs", {})
            return device.eki_channel(m, key, channel, where, config=configs.get(channel.upper()))
        if key in GET_TYPES:
            if setters is None or setters[2] is None:
                raise RunError(f"{where}: {name}: the value (OUT) is a variable")
            result, value = device.eki_channel(m, key, channel, where, path=path, type_name=GET_TYPES[key])
            if value is not None:
                setters[2](fr, value)
            return result
        value = args[2] if arity > 2 else None
        return device.eki_channel(m, key, channel, where, path=path, value=value)

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
