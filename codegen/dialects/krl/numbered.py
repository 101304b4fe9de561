"""The controller's numbered data TOOL_DATA, BASE_DATA, LOAD_DATA: their sizes and a fresh controller's values."""

from __future__ import annotations

from codegen.dialects.core.values import Record, f32
from codegen.dialects.krl.builtins import frame

# KUKA's $config.dat: the numbered tools, bases and loads (type, size, what an --input gives)
SYSTEM_ARRAYS = {
    "BASE_DATA": ("FRAME", 32, "X,Y,Z,A,B,C"),
    "TOOL_DATA": ("FRAME", 16, "X,Y,Z,A,B,C"),
    "LOAD_DATA": ("LOAD", 16, "M,X,Y,Z[,A,B,C,JX,JY,JZ] (kg, centre of gravity mm, principal axes deg, kg m2)"),
}

# A fresh controller's numbered data (what an unused entry of a stock $config.dat holds, seen in controllers'
# backups: TOOL_DATA and BASE_DATA {X 0.0, Y 0.0, Z 0.0, A 0.0, B 0.0, C 0.0}, LOAD_DATA {M -1.0, CM {all 0},
# J {all 0}}: mass -1, the load not given). An entry the program's files and --input leave so is used as such,
# and the run warns, naming it (fresh_warning).
FRESH_SHOWN = {"FRAME": "a zero frame", "LOAD": "M -1: no load given"}


def fresh_entry(type_name: str) -> Record:
    if type_name == "FRAME":
        return frame((0, 0, 0, 0, 0, 0))
    return Record("LOAD", {"M": f32(-1.0), "CM": frame((0, 0, 0, 0, 0, 0)), "J": no_inertia()})


def no_inertia() -> Record:
    return Record("INERTIA", {"X": f32(0), "Y": f32(0), "Z": f32(0)})


def fresh_values(m, array: str) -> list:
    """The run's values of TOOL_DATA / BASE_DATA / LOAD_DATA: as the program, its $config.dat and --input left
    them, the entries nobody set as a fresh controller has them (each known by identity, to warn where used)."""
    values = m.state.sysvars.get(array)
    if values is None:
        type_name, size, _shape = SYSTEM_ARRAYS[array]
        values = [fresh_entry(type_name) for _ in range(size)]
        for i, value in enumerate(values, start=1):
            m.state.fresh[id(value)] = (f"{array}[{i}]", value)  # the value kept: its id stays its own
        m.state.sysvars[array] = values
    return values


def fresh_warning(m, value) -> None:
    """A warning where value is an entry of the numbered data that nothing set (fresh_values)."""
    entry = m.state.fresh.get(id(value))
    if entry is None or entry[1] is not value:
        return
    name = entry[0]
    array = name.split("[", 1)[0]
    shape = SYSTEM_ARRAYS[array][2]
    m.warn(
        f"{name} is not set in the program's files: taken as a fresh controller has it "
        f"({FRESH_SHOWN[value.type]}); give it with --input {name}={shape} or a $config.dat among the files"
    )
