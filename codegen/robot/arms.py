"""The arm catalogue (codegen/robot/catalogue.toml) and custom arms given by their parameters."""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from functools import cache, cached_property
from pathlib import Path

import numpy as np

from codegen.robot.opw import OPW
from codegen.robot.urdh import URDH

CATALOGUE = Path(__file__).with_name("catalogue.toml")
FAMILIES = {"opw": OPW, "ur": URDH}
_OPW_KEYS = ("a1", "a2", "b", "c1", "c2", "c3", "c4")
_UR_KEYS = ("d1", "a2", "a3", "d4", "d5", "d6")
PARAM_BOUND_MM = 10_000.0  # no arm in the catalogue is within a factor of three of this
PAYLOAD_BOUND_KG = 2_500.0  # over ten times the catalogue's largest payload (210 kg): a typing error beyond


class ArmError(Exception):
    """An arm description that cannot be used; the message names the key (the caller adds the file)."""


@dataclass(frozen=True)
class LinkShape:
    """One capsule of an arm's shape: the segment a-b (mm) fixed in link frame `frame` (the family's link_frames,
    0 the base .. 6 the flange) and its radius (mm)."""

    name: str
    frame: int
    a: tuple[float, float, float]
    b: tuple[float, float, float]
    radius: float


@dataclass(frozen=True)
class Arm:
    model: str
    vendor: str  # the controller family that drives it: a target's `vendor` fact (targets/<t>.toml)
    family: str  # "opw" (ortho-parallel with a spherical wrist) or "ur" (UR-type DH)
    kin: OPW | URDH
    limits_deg: tuple[tuple[float, float], ...]  # software limits per axis
    home_deg: tuple[float, ...]
    reach_mm: float | None = None
    payload_kg: float | None = None
    source: str = ""
    links: tuple[LinkShape, ...] = ()  # the arm's shape (codegen/world); empty: none declared
    self_allowed: tuple[tuple[int, int], ...] = ()  # link-frame pairs not checked against each other
    links_source: str = ""

    @cached_property
    def limits(self) -> np.ndarray:
        """limits_deg as a read-only (6, 2) array (made once: every solved move reads it)."""
        out = np.array(self.limits_deg, dtype=float)
        out.flags.writeable = False
        return out

    def __getstate__(self) -> dict:
        """Pickled without the made limits (a worker process makes its own, read-only again)."""
        return {key: value for key, value in self.__dict__.items() if key != "limits"}


def _number(value, path: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ArmError(f"{path}: expected a finite number, got {_shown(value)}")
    try:
        number = float(value)
    except OverflowError:  # an integer beyond a float64
        number = math.inf
    if not math.isfinite(number):
        raise ArmError(f"{path}: expected a finite number, got {_shown(value)}")
    return number


def _shown(value) -> str:
    """A value as a message shows it (an integer of hundreds of digits by its length)."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10**12:
        return f"an integer of {len(str(abs(value))) if value.bit_length() < 10_000 else 'thousands of'} digits"
    return repr(value) if not isinstance(value, list | dict) else f"a {type(value).__name__}"


def _positive(table: dict, key: str, path: str, high: float, unit: str) -> float | None:
    """An optional positive number within high (reach_mm, payload_kg)."""
    if table.get(key) is None:
        return None
    value = _number(table[key], f"{path}.{key}")
    if not 0 < value <= high:
        raise ArmError(f"{path}.{key}: expected a value in (0, {high:g}] {unit}, got {value:g}")
    return value


def _numbers(value, count: int, path: str) -> tuple[float, ...]:
    if not isinstance(value, list) or len(value) != count:
        raise ArmError(f"{path}: expected {count} numbers")
    return tuple(_number(v, f"{path}[{i}]") for i, v in enumerate(value))


def arm_from_table(table: dict, path: str, model: str | None = None) -> Arm:
    """An arm from its description: catalogue entries and a cell's custom arm share this."""
    allowed = {"model", "vendor", "family", "params", "limits_deg", "home_deg", "reach_mm", "payload_kg", "source"}
    allowed |= {"links", "self_allowed", "links_source"}
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise ArmError(f"{path}.{unknown[0]}: unknown key; allowed: {', '.join(sorted(allowed))}")
    for key in ("family", "params", "limits_deg", "home_deg"):
        if key not in table:
            raise ArmError(f"{path}.{key}: missing")
    family = table["family"]
    if not isinstance(family, str) or family not in FAMILIES:
        raise ArmError(f"{path}.family: expected one of {', '.join(FAMILIES)}, got {_shown(family)}")
    params = table["params"]
    if not isinstance(params, dict):
        raise ArmError(f"{path}.params: expected a table")
    lengths = _OPW_KEYS if family == "opw" else _UR_KEYS
    extra = ("offsets_deg", "signs") if family == "opw" else ()
    unknown = sorted(set(params) - set(lengths) - set(extra))
    if unknown:
        raise ArmError(f"{path}.params.{unknown[0]}: unknown key; allowed: {', '.join(lengths + extra)}")
    values = {}
    for key in lengths:
        if key not in params:
            raise ArmError(f"{path}.params.{key}: missing")
        values[key] = _number(params[key], f"{path}.params.{key}")
        if abs(values[key]) > PARAM_BOUND_MM:
            raise ArmError(f"{path}.params.{key}: beyond +-{PARAM_BOUND_MM:g} mm")
    if family == "opw":
        values["offsets_deg"] = _numbers(params.get("offsets_deg", [0] * 6), 6, f"{path}.params.offsets_deg")
        if max(abs(v) for v in values["offsets_deg"]) > 360:
            raise ArmError(f"{path}.params.offsets_deg: expected angles within +-360 deg (one turn)")
        signs = params.get("signs", [1] * 6)
        bad = [s for s in signs if isinstance(s, bool) or s not in (1, -1)] if isinstance(signs, list) else [signs]
        if bad or len(signs) != 6:
            raise ArmError(f"{path}.params.signs: expected 6 values of 1 or -1")
        values["signs"] = tuple(int(s) for s in signs)
    kin = FAMILIES[family](**values)
    limits_raw = table["limits_deg"]
    if not isinstance(limits_raw, list) or len(limits_raw) != 6:
        raise ArmError(f"{path}.limits_deg: expected 6 pairs [low, high]")
    limits = tuple(_numbers(pair, 2, f"{path}.limits_deg[{i}]") for i, pair in enumerate(limits_raw))
    for i, (low, high) in enumerate(limits):
        if not -720 <= low < high <= 720:
            raise ArmError(f"{path}.limits_deg[{i}]: expected low < high within +-720 deg")
    home = _numbers(table["home_deg"], 6, f"{path}.home_deg")
    check_inside(home, limits, f"{path}.home_deg")
    vendor = table.get("vendor", "")
    if not isinstance(vendor, str):
        raise ArmError(f"{path}.vendor: expected a string")
    name = model or table.get("model")
    if not isinstance(name, str) or not name.strip():
        raise ArmError(f"{path}.model: expected a non-empty string")
    return Arm(
        model=name,
        vendor=vendor,
        family=family,
        kin=kin,
        limits_deg=limits,
        home_deg=home,
        reach_mm=_positive(table, "reach_mm", path, PARAM_BOUND_MM, "mm"),
        payload_kg=_positive(table, "payload_kg", path, PAYLOAD_BOUND_KG, "kg"),
        source=str(table.get("source", "")),
        links=_links(table.get("links", []), f"{path}.links"),
        self_allowed=_pairs(table.get("self_allowed", []), f"{path}.self_allowed"),
        links_source=str(table.get("links_source", "")),
    )


def _links(value, path: str) -> tuple[LinkShape, ...]:
    """The capsules of an arm's `links` key."""
    if not isinstance(value, list):
        raise ArmError(f"{path}: expected a list of tables")
    out = []
    for i, row in enumerate(value):
        where = f"{path}[{i}]"
        if not isinstance(row, dict):
            raise ArmError(f"{where}: expected a table {{ name, frame, a, b, radius }}")
        unknown = sorted(set(row) - {"name", "frame", "a", "b", "radius"})
        if unknown:
            raise ArmError(f"{where}.{unknown[0]}: unknown key; allowed: a, b, frame, name, radius")
        for key in ("name", "frame", "a", "b", "radius"):
            if key not in row:
                raise ArmError(f"{where}.{key}: missing")
        frame = row["frame"]
        if isinstance(frame, bool) or not isinstance(frame, int) or not 0 <= frame <= 6:
            raise ArmError(f"{where}.frame: expected an integer 0 .. 6")
        radius = _number(row["radius"], f"{where}.radius")
        if not 0 < radius <= PARAM_BOUND_MM:
            raise ArmError(f"{where}.radius: expected a value in (0, {PARAM_BOUND_MM:g}] mm")
        a, b = (_numbers(row[key], 3, f"{where}.{key}") for key in ("a", "b"))
        if max(abs(v) for v in a + b) > PARAM_BOUND_MM:
            raise ArmError(f"{where}: a point beyond +-{PARAM_BOUND_MM:g} mm")
        out.append(LinkShape(str(row["name"]), frame, a, b, radius))  # type: ignore[arg-type]
    return tuple(out)


def _pairs(value, path: str) -> tuple[tuple[int, int], ...]:
    """The link-frame pairs of `self_allowed`."""
    if not isinstance(value, list):
        raise ArmError(f"{path}: expected a list of [i, j] pairs")
    out = []
    for i, pair in enumerate(value):
        ok = isinstance(pair, list) and len(pair) == 2
        ok = ok and all(isinstance(v, int) and not isinstance(v, bool) and 0 <= v <= 6 for v in pair)
        if not ok:
            raise ArmError(f"{path}[{i}]: expected a pair [i, j] of link frames 0 .. 6")
        out.append((min(pair), max(pair)))
    return tuple(out)


def check_inside(joints: tuple[float, ...], limits, path: str) -> None:
    for i, (q, (low, high)) in enumerate(zip(joints, limits, strict=True)):
        if not low <= q <= high:
            raise ArmError(f"{path}[{i}]: axis {i + 1} at {q:g} deg is outside its limits [{low:g}, {high:g}]")


@cache
def catalogue() -> dict[str, Arm]:
    """Every arm of the catalogue by model name (the vendor's own spelling)."""
    data = tomllib.loads(CATALOGUE.read_text(encoding="utf-8"))
    arms: dict[str, Arm] = {}
    for i, table in enumerate(data["arm"]):
        arm = arm_from_table(table, f"{CATALOGUE.name}: arm[{i}]")
        if arm.model in arms:
            raise ArmError(f"{CATALOGUE.name}: arm[{i}].model: {arm.model!r} listed twice")
        arms[arm.model] = arm
    return arms


def find_arm(model: str) -> Arm | None:
    """A catalogue arm by name, ignoring case and spacing ("kr10 r1100 sixx" finds "KR 10 R1100 sixx")."""
    arms = catalogue()
    if model in arms:
        return arms[model]
    key = "".join(model.lower().split())
    for name, arm in arms.items():
        if "".join(name.lower().split()) == key:
            return arm
    return None
