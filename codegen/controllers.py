"""Registry of controller targets, discovered from targets/<name>.toml (vendor facts with sources)."""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from codegen import data_dir

TARGETS_DIR = data_dir("targets")
IDENTIFIER_CASES = ("as_written", "upper")
# how a taught pose names its arm configuration (codegen/robot/config.py FORMS), or "none": no arm at all
CONFIGURATIONS = ("confdata", "status_turn", "joints", "none")


class TargetError(Exception):
    """A targets/<name>.toml that is missing a fact or names an unknown one."""


@dataclass(frozen=True)
class Target:
    """One controller: every key of its TOML file as a typed field (unknown keys are refused)."""

    name: str
    title: str
    dialect: str  # a folder of codegen/dialects
    pose_format: str  # a convention of codegen.poses.POSE_FORMATS
    pose_units: str  # how a pose of that format reads, for reports
    files: tuple[str, ...]  # output file names, "{cell}" replaced; the first is the program
    numbers: str  # "float32" or "float64": the controller's number type (verify's tolerance)
    identifier_max: int
    identifier_case: str  # how generated identifiers are written: IDENTIFIER_CASES
    identifier_case_sensitive: bool
    string_max: int
    vendor: str  # the arms its controller drives (codegen/robot/catalogue.toml), "none" without a robot
    configuration: str  # how a taught pose names its arm configuration (codegen/robot/config.py)
    sources: tuple[str, ...]
    program: dict  # the [program] table: names and settings the templates and verify read
    kind_tables: dict  # [program.<kind>] tables: each program kind's own facts, checked by the kind (codegen.protocol)

    @property
    def suffixes(self) -> tuple[str, ...]:
        return tuple("." + f.rsplit(".", 1)[1].lower() for f in self.files)


_SCALARS = {
    "name": str,
    "title": str,
    "dialect": str,
    "pose_format": str,
    "pose_units": str,
    "numbers": str,
    "identifier_max": int,
    "identifier_case": str,
    "identifier_case_sensitive": bool,
    "string_max": int,
    "vendor": str,
    "configuration": str,
}


# The [program] table: what the templates and verify read, with its type; the first three are required.
_PROGRAM = {
    "joint_move": str,  # the joint move instruction, or its arguments (UR)
    "linear_move": str,
    "inputs": dict,  # station, x, y, theta: the vision interface's names (`codegen run --input`, verify)
    "photo": dict,  # request, ack, u, v, angle: the photo handshake's names (frame kind)
    # the network channel the program reaches the vision PC through (codegen.sim.vision_pc CHANNELS): its form, the
    # element paths of the request sent (command, request) and of the answer received (ack and the answer's names)
    "channel": dict,
    "speed": str,
    "zone": str,
    "tool": str,
    "log_decimals": int,  # decimals of the logged numbers, when the program rounds them
    "message_module": str,
    "station_register": int,
    "mark_registers": list,
    "photo_registers": dict,
    "level_frames_only": bool,  # frames compose only in the x-y plane
    "base_data": dict,  # name ("...{n}...") and max of the controller's numbered bases
    "joint_unit": str,  # "deg" or "rad": how the language writes joint positions
    "tool_data": dict,  # tool and load ("...{n}...") and max of the controller's numbered tools and loads
    "restart": str,  # "at_home": refuses to start away from home; "bco": a PTP home from anywhere; "none"
    "signals": dict,  # digital I/O ([cell.io]): form "index" (range) or "name"; output and input ("...{n}...")
    "signal_cycle_s": float,  # how often the controller sees an input change while the arm moves (s)
    "minimum_release": str,  # the controller software every program needs (a header line of each program)
}
_PROGRAM_REQUIRED = ("joint_move", "linear_move", "inputs")


def _load(path: Path) -> Target:
    try:
        facts = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise TargetError(f"{path}: {exc}") from None
    known = {*_SCALARS, "files", "sources", "program"}
    unknown = sorted(set(facts) - known)
    if unknown:
        raise TargetError(f"{path}: {unknown[0]}: unknown key (a fact no code reads belongs in a comment)")
    missing = sorted(known - set(facts))
    if missing:
        raise TargetError(f"{path}: {missing[0]}: missing")
    for key, kind in _SCALARS.items():
        if not isinstance(facts[key], kind):
            raise TargetError(f"{path}: {key}: expected {kind.__name__}")
    if facts["name"] != path.stem:
        raise TargetError(f"{path}: name: must be the file's name {path.stem!r}")
    if facts["identifier_case"] not in IDENTIFIER_CASES:
        raise TargetError(f"{path}: identifier_case: expected one of {', '.join(IDENTIFIER_CASES)}")
    if facts["configuration"] not in CONFIGURATIONS:
        raise TargetError(f"{path}: configuration: expected one of {', '.join(CONFIGURATIONS)}")
    if (facts["configuration"] == "none") != (facts["vendor"] == "none"):
        raise TargetError(
            f"{path}: vendor and configuration: a target has both an arm vendor and a configuration, or neither"
        )
    if not facts["sources"]:
        raise TargetError(f"{path}: sources: each target cites where its facts come from")
    program = {k: v for k, v in facts["program"].items() if k in _PROGRAM or not isinstance(v, dict)}
    kind_tables = {k: v for k, v in facts["program"].items() if k not in program}
    unknown_program = sorted(set(program) - set(_PROGRAM))
    if unknown_program:
        raise TargetError(f"{path}: program.{unknown_program[0]}: unknown key; known: {', '.join(_PROGRAM)}")
    for key in _PROGRAM_REQUIRED:
        if key not in program:
            raise TargetError(f"{path}: program.{key}: missing")
    for key, value in program.items():
        if isinstance(value, bool) is not (_PROGRAM[key] is bool) or not isinstance(value, _PROGRAM[key]):
            raise TargetError(f"{path}: program.{key}: expected {_PROGRAM[key].__name__}")
    return Target(
        **{key: facts[key] for key in _SCALARS},
        files=tuple(facts["files"]),
        sources=tuple(facts["sources"]),
        program=program,
        kind_tables=kind_tables,
    )


@cache
def targets() -> dict[str, Target]:
    """Every targets/*.toml, by name, in name order."""
    return {path.stem: _load(path) for path in sorted(TARGETS_DIR.glob("*.toml"))}


def target_names() -> tuple[str, ...]:
    return tuple(targets())


def get_target(name: str) -> Target:
    known = targets()
    if name not in known:
        raise KeyError(f"unknown target {name!r}; known: {', '.join(known)}")
    return known[name]


def all_targets() -> list[Target]:
    return list(targets().values())


def target_of_suffix(suffix: str) -> Target | None:
    """The target whose output files end in `suffix` (a program or a companion file)."""
    for target in targets().values():
        if suffix.lower() in target.suffixes:
            return target
    return None


def target_of_language(dialect_name: str) -> Target | None:
    """The one target whose programs are written in the dialect `dialect_name`, None if none or several: a file
    whose suffix only the language knows (URScript `.urscript`, RAPID `.modx`), not one codegen writes."""
    found = [target for target in targets().values() if target.dialect == dialect_name]
    return found[0] if len(found) == 1 else None


def numbered_names(target_name: str, number: int) -> tuple[str, str]:
    """The controller's numbered tool and load variables (e.g. TOOL_DATA[3], LOAD_DATA[3])."""
    facts = get_target(target_name).program["tool_data"]
    return facts["tool"].format(n=number), facts["load"].format(n=number)
