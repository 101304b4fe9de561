"""RAPID's predefined data (the BASE module and the data types' predefined values): v5..vmax, z0..z200, fine, tool0."""

from __future__ import annotations

from codegen.dialects.core.values import Record, f32
from codegen.dialects.rapid.types import RECORDS

# Sources: ABB, "Technical reference manual - RAPID Instructions, Functions and Data types" (RobotWare 6 and 7),
# data types speeddata, zonedata, tooldata, wobjdata and loaddata, section "Predefined data". The manual's text
# was not readable during this work; the values below are as recalled and agree with a public library's table of
# the same predefined data (RobotComponents, SpeedData and ZoneData) and with the BASE module it writes:
# - speeddata v5 ... v7000: [v_tcp = N mm/s, v_ori 500 deg/s, v_leax 5000 mm/s, v_reax 1000 deg/s]; vmax: the
#   robot type's maximum TCP speed (later manuals: MaxRobSpeed(); 5000 mm/s here, uncertain); vrot1 ... vrot100
#   [0, N deg/s, 0, 0] and vlin10 ... vlin1000 [0, 0, N mm/s, 0] for external axes (recalled, not confirmed);
# - zonedata fine [TRUE, 0, 0, 0, 0, 0, 0] (a stop point); z0 ... z200 [FALSE, pzone_tcp, pzone_ori, pzone_eax,
#   zone_ori, zone_leax, zone_reax] in the table below;
# - tool0 [TRUE, [[0, 0, 0], [1, 0, 0, 0]], load0] (the flange), wobj0 [FALSE, TRUE, "", identity, identity] (the
#   world frame), load0 [0.001, [0, 0, 0.001], [1, 0, 0, 0], 0, 0, 0].
SPEEDS = (
    5,
    10,
    20,
    30,
    40,
    50,
    60,
    80,
    100,
    150,
    200,
    300,
    400,
    500,
    600,
    800,
    1000,
    1500,
    2000,
    2500,
    3000,
    4000,
    5000,
    6000,
    7000,
)
VMAX_TCP = 5000.0
ROTATIONS = (1, 2, 5, 10, 20, 50, 100)
LINEARS = (10, 20, 50, 100, 200, 500, 1000)
ZONES = {  # name: (pzone_tcp mm, pzone_ori mm, pzone_eax mm, zone_ori deg, zone_leax mm, zone_reax deg)
    "Z0": (0.3, 0.3, 0.3, 0.03, 0.3, 0.03),
    "Z1": (1, 1, 1, 0.1, 1, 0.1),
    "Z5": (5, 8, 8, 0.8, 8, 0.8),
    "Z10": (10, 15, 15, 1.5, 15, 1.5),
    "Z15": (15, 23, 23, 2.3, 23, 2.3),
    "Z20": (20, 30, 30, 3, 30, 3),
    "Z30": (30, 45, 45, 4.5, 45, 4.5),
    "Z40": (40, 60, 60, 6, 60, 6),
    "Z50": (50, 75, 75, 7.5, 75, 7.5),
    "Z60": (60, 90, 90, 9, 90, 9),
    "Z80": (80, 120, 120, 12, 120, 12),
    "Z100": (100, 150, 150, 15, 150, 15),
    "Z150": (150, 225, 225, 23, 225, 23),
    "Z200": (200, 300, 300, 30, 300, 30),
}


def _record(type_name: str, values) -> Record:
    fields = RECORDS[type_name]
    out = {}
    for (key, kind), value in zip(fields, values, strict=True):
        if kind in RECORDS:
            out[key] = _record(kind, value)
        elif kind == "NUM":
            out[key] = f32(value)
        else:
            out[key] = value
    return Record(type_name, out)


IDENTITY = [[0, 0, 0], [1, 0, 0, 0]]
LOAD0 = [0.001, [0, 0, 0.001], [1, 0, 0, 0], 0, 0, 0]

PREDEFINED: dict[str, Record] = {}
for _v in SPEEDS:
    PREDEFINED[f"V{_v}"] = _record("SPEEDDATA", (_v, 500, 5000, 1000))
PREDEFINED["VMAX"] = _record("SPEEDDATA", (VMAX_TCP, 500, 5000, 1000))
for _v in ROTATIONS:
    PREDEFINED[f"VROT{_v}"] = _record("SPEEDDATA", (0, _v, 0, 0))
for _v in LINEARS:
    PREDEFINED[f"VLIN{_v}"] = _record("SPEEDDATA", (0, 0, _v, 0))
PREDEFINED["FINE"] = _record("ZONEDATA", (True, 0, 0, 0, 0, 0, 0))
for _name, _zone in ZONES.items():
    PREDEFINED[_name] = _record("ZONEDATA", (False, *_zone))
PREDEFINED["LOAD0"] = _record("LOADDATA", LOAD0)
PREDEFINED["TOOL0"] = _record("TOOLDATA", (True, IDENTITY, LOAD0))
PREDEFINED["WOBJ0"] = _record("WOBJDATA", (False, True, "", IDENTITY, IDENTITY))

# The system module USER's data (RobotWare's USER.sys, as recalled): variables a program may use without declaring
# them, as every task has them: VAR num reg1 ... reg5 (0 at the start) and VAR clock clock1.
USER_DATA = {**{f"REG{i}": "NUM" for i in range(1, 6)}, "CLOCK1": "CLOCK"}

# A predefined datum by identity: a move's settings name it (values are never changed in place, so a variable
# that was given v100 holds this very record until it is given another value).
NAMES: dict[int, str] = {id(record): name for name, record in PREDEFINED.items()}
TOOL0, WOBJ0 = PREDEFINED["TOOL0"], PREDEFINED["WOBJ0"]


def name_of(value) -> str | None:
    """The predefined datum's name (upper case) when value is one, else None."""
    return NAMES.get(id(value))
