"""The station kind's section of a cell: [cell.camera] (angle sign, hand-eye map), [cell.limits], the modes'
settings and the [[station]] tables, read and checked (errors name the file and the key path)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property, partial
from itertools import pairwise
from typing import Any

from codegen import protocol
from codegen.kinds.station.keys import (
    GRIP,
    NAME,
    RELEASE,
    VISION_TABLES,
    camera,
    default_mode,
    kind_keys,
    limits,
    station_table,
)
from codegen.kinds.station.mode import modes
from codegen.kinds.station.part import Part, read_part
from codegen.model import motion
from codegen.model.cell import TaughtPose
from codegen.model.loader import Loader, build
from codegen.model.robot import check_carried, parse_station_config
from codegen.model.validate import kind_of
from codegen.model.world import parse_solids
from codegen.poses import POSE_FORMATS

STATIONS_MAX = 5000  # the largest cell measured: its programs load and run here (a UR program in about 35 s)
POSES_MAX = 1000  # a station's poses are one run: 1,000 take about a tenth of verify's step limit


@dataclass(frozen=True)
class Limits:
    max_shift_mm: float
    max_rotation_deg: float


@dataclass(frozen=True)
class Station:
    id: int
    name: str
    poses: tuple[TaughtPose, ...]  # visiting order: first joint move, then linear
    mode: str  # the station's mode (codegen/kinds/station/modes/): the cell file's `mode` key
    spec: Any  # the mode's own data, e.g. the calibration mark or frame
    config: dict = field(default_factory=dict, compare=False)  # target -> pose -> PoseConfig ([station.config])
    retreat: TaughtPose | None = None  # the work pose backed off along its z axis ([cell.motion] retreat_mm)
    # ([station.gripper]) (pose name, GRIP or RELEASE) in visiting order: what the gripper does at that pose
    gripper: tuple[tuple[str, str], ...] = ()
    part: Part | None = None  # ([station.part]) the part the gripper carries: its size, mass, centre of gravity
    solids: dict = field(default_factory=dict, compare=False)  # ([station.solids]) name -> SolidSpec at calibration

    def action(self, pose_name: str) -> str | None:
        """What the gripper does once the arm stands at the pose (GRIP, RELEASE), None: nothing."""
        return dict(self.gripper).get(pose_name)

    @property
    def holds_at_start(self) -> bool | None:
        """Whether the station expects a part in the gripper when it starts (its first action puts one down), None:
        the gripper does nothing in the station."""
        return None if not self.gripper else self.gripper[0][1] == RELEASE

    @property
    def path(self) -> tuple[TaughtPose, ...]:
        """The poses the arm visits in the station: the taught ones (the last is the work pose), then
        the retreat."""
        return self.poses if self.retreat is None else (*self.poses, self.retreat)


@dataclass(frozen=True)
class StationSection:
    """The stations of a cell and what their readings are checked against."""

    angle_sign: int
    limits: Limits
    stations: tuple[Station, ...]
    handeye: tuple[tuple[float, float, float], tuple[float, float, float]] | None = None  # pixel -> mm
    settings: dict = field(default_factory=dict, compare=False)  # mode name -> its [cell.<table>] settings

    def station_by_id(self, station_id: int) -> Station | None:
        return self._stations_by_id.get(station_id)

    @cached_property
    def _stations_by_id(self) -> dict[int, Station]:
        return {station.id: station for station in self.stations}


def section_of(cell) -> StationSection | None:
    """The cell's station section (None: the cell has no [[station]])."""
    return cell.sections.get(NAME)


def stations_of(cell) -> tuple[Station, ...]:
    section = section_of(cell)
    return () if section is None else section.stations


def station_label(cell, station: Station) -> str:
    """A station as the cell file's messages name it: its [[station]] entry by position from 0, as the loader names
    its keys (station[0]), and its name."""
    index = next(i for i, s in enumerate(stations_of(cell)) if s.id == station.id)
    return f"station[{index}] {station.name!r}"


def with_section(cell, **changes):
    """The cell with its station section changed (verify's extra stations, the mutation tests)."""
    return replace(cell, sections={**cell.sections, NAME: replace(section_of(cell), **changes)})


def image_angle_sign(pixel_to_mm) -> int:
    """The angle sign a camera's image imposes: -1 when the hand-eye map mirrors (negative determinant),
    since a turn of the mark then turns the other way in the image's axes."""
    (a, b, _), (c, d, _) = pixel_to_mm
    return -1 if a * d - b * c < 0 else 1


def parse(ctx, data: dict, cell, standalone: bool) -> StationSection | None:
    """The section from the cell file's tables (None: a cell of a standalone kind without [[station]]); cell: the
    cell as far as it is known (pose format, arm, motion)."""
    cell_table = data["cell"]
    vision_free = not data.get(NAME) and standalone
    if vision_free:  # a cell of a kind that reads no mark needs no camera and no limits
        camera_unused, limits_unused = VISION_TABLES
        unused = {camera_unused: {"angle_sign": 1}, limits_unused: {"max_shift_mm": 10.0, "max_rotation_deg": 10.0}}
        cell_table = {**unused, **cell_table}
    angle_sign, handeye = _camera(ctx, cell_table)
    settings = {name: mode.parse_settings(ctx, cell_table) for name, mode in modes().items()}
    bounds = _limits(ctx, cell_table)

    stations_raw = data.get(NAME, [] if vision_free else None)
    if not isinstance(stations_raw, list) or not (stations_raw or vision_free):
        ctx.fail("station", "expected at least one [[station]] table, or the tables of a program kind that needs none")
    if len(stations_raw) > STATIONS_MAX:
        ctx.fail(
            "station",
            f"{len(stations_raw)} stations; at most {STATIONS_MAX} (the largest cell whose programs are verified "
            "to load and run in the interpreter here)",
        )
    if not stations_raw:
        return None
    pose_format = cell.pose_format
    loader = Loader(ctx, pose_format)
    stations = [_station(ctx, loader, raw, i) for i, raw in enumerate(stations_raw)]
    stations = [
        replace(
            station,
            config=parse_station_config(
                ctx, raw.get("config"), f"station[{i}].config", cell.robot, [p.name for p in station.poses]
            ),
        )
        for i, (station, raw) in enumerate(zip(stations, stations_raw, strict=True))
    ]
    if cell.motion.retreat_mm > 0:
        stations = [replace(s, retreat=_retreat(s, cell.motion.retreat_mm, pose_format)) for s in stations]
    for i, station in enumerate(stations):
        if station.gripper and (cell.io is None or set(cell.io.output) - set(cell.io.feedback)):
            ctx.fail(
                f"station[{i}].gripper",
                "the gripper needs [cell.io] with its feedback on every target: the program confirms each grip and "
                "release, and whether it holds a part when it starts",
            )
    seen_ids: dict[int, int] = {}
    seen_names: dict[str, int] = {}
    for i, station in enumerate(stations):
        if station.id in seen_ids:
            ctx.fail(f"station[{i}].id", f"duplicate station id {station.id} (also station[{seen_ids[station.id]}])")
        if station.name in seen_names:
            other = seen_names[station.name]
            ctx.fail(f"station[{i}].name", f"duplicate station name {station.name!r} (also station[{other}])")
        seen_ids[station.id] = i
        seen_names[station.name] = i
    return StationSection(int(angle_sign), bounds, tuple(stations), handeye, settings)


def _camera(ctx, cell_table: dict):
    """[cell.camera] read by its declaration (camera()), with the hand-eye map's own rules: a map that inverts, and
    the angle sign its image imposes."""
    values = Loader(ctx).table(camera(), ctx.table(cell_table, "camera", "cell.camera"), "cell.camera")
    angle_sign = values["angle_sign"]
    if values["handeye"] is None:
        return angle_sign, None
    handeye = values["handeye"]["pixel_to_mm"]
    det = handeye[0][0] * handeye[1][1] - handeye[0][1] * handeye[1][0]
    if not abs(det) >= 1e-12:
        ctx.fail("cell.camera.handeye.pixel_to_mm", "the 2x2 part is singular: the map cannot be inverted")
    if angle_sign != image_angle_sign(handeye):
        ctx.fail(
            "cell.camera.angle_sign",
            f"the hand-eye map's determinant is {'negative' if det < 0 else 'positive'}: the image is "
            f"{'' if det < 0 else 'not '}mirrored, so the camera's angles turn "
            f"{'against' if det < 0 else 'with'} the frame's and angle_sign must be {image_angle_sign(handeye)} "
            "(`codegen calibrate handeye POINTS.csv --write CELL` sets it)",
        )
    return angle_sign, handeye


def _shift_within_reach(ctx, max_shift_mm: float, arms: dict) -> None:
    """A shift no arm can follow is refused before its envelope is sampled: the disc of readings around a taught pose
    fits in the arm's reach only when its radius is within the reach (the sampling grows with the radius, so a
    typing error would otherwise cost minutes and gigabytes before the same refusal)."""
    for target, arm in arms.items():
        if arm.reach_mm is not None and max_shift_mm > arm.reach_mm:
            ctx.fail(
                "cell.limits.max_shift_mm",
                f"{max_shift_mm:g} mm is more than the {arm.model}'s reach of {arm.reach_mm:g} mm "
                f"(cell.robot.{target}): no taught pose can be followed over that shift",
            )


def _limits(ctx, cell_table: dict) -> Limits:
    """[cell.limits] read by its declaration (limits())."""
    return build(Limits, Loader(ctx).table(limits(), ctx.table(cell_table, "limits", "cell.limits"), "cell.limits"))


def _station(ctx, loader: Loader, raw, index: int) -> Station:
    """One [[station]]: its mode first (it decides the station's other keys), then its keys as declared (keys.py) and
    the rules between them."""
    path = f"station[{index}]"
    if not isinstance(raw, dict):
        ctx.fail(path, f"expected a table, got {kind_of(raw)}")
    known = modes()
    mode_name = loader.value(station_table()["mode"], raw.get("mode", default_mode()), f"{path}.mode")
    table = station_table(mode_name)
    for key in sorted(set(raw) - table.allowed):
        owners = [m.name for m in known.values() if key in m.station_keys()]
        if owners:
            ctx.fail(f"{path}.{key}", f'only {owners[0]} stations (mode = "{owners[0]}") have this key')
    poses_raw = raw.get("poses")
    if isinstance(poses_raw, dict) and len(poses_raw) > POSES_MAX:  # refused before so many are read
        ctx.fail(f"{path}.poses", f"{len(poses_raw)} poses; at most {POSES_MAX} per station")
    passed = {"config": lambda value, where: value, "part": lambda value, where: value,
              "solids": lambda value, where: value}  # config read with the arms, part by read_part, solids by world
    values = loader.table(table, raw, path, readers=passed)
    spec = known[mode_name].parse(ctx, values, path)
    poses = tuple(values["poses"].values())
    gripper = _gripper(ctx, values["gripper"] or {}, path, list(values["poses"]))
    part = read_part(ctx, raw.get("part"), f"{path}.part")
    solids = parse_solids(ctx, raw.get("solids"), f"{path}.solids", loader.pose_format)
    return Station(values["id"], values["name"], poses, mode_name, spec, gripper=gripper, part=part, solids=solids)


def _gripper(ctx, table: dict, path: str, pose_names: list[str]) -> tuple[tuple[str, str], ...]:
    """[station.gripper] in visiting order: every name a pose of the station, and grip and release alternating (a
    part taken is put down before the next is taken; a first release puts down a part the program starts with)."""
    for name in table:
        if name not in pose_names:
            ctx.fail(f"{path}.gripper.{name}", f"not a pose of the station; its poses: {', '.join(pose_names)}")
    actions = tuple((name, table[name]) for name in pose_names if name in table)
    for (before, first), (name, second) in pairwise(actions):
        if first == second:
            what = "it already holds the part taken" if first == GRIP else "it holds nothing since the release"
            ctx.fail(f"{path}.gripper.{name}", f"{second} after {first} at {before!r}: {what} (they alternate)")
    return actions


def _retreat(station: Station, retreat_mm: float, pose_format: str) -> TaughtPose:
    """The station's work pose backed off along its own z axis, in the cell's pose format."""
    work2base = station.poses[-1].matrix() @ motion.retreat2work(retreat_mm)
    values = tuple(float(v) + 0.0 for v in POSE_FORMATS[pose_format][2](work2base))  # + 0.0: no -0.0
    return TaughtPose("retreat", values, pose_format)


class SectionPart(protocol.Section):
    """The station kind's tables: [cell.camera], [cell.limits], the modes' settings and the [[station]] tables."""

    @property
    def keys(self):
        return kind_keys()  # the modes' keys with the kind's: read once the modes are registered

    def listed_names(self) -> tuple[str, ...]:
        return tuple(modes())

    def starters(self) -> dict:
        from codegen.kinds.station.starter import mode_starter

        return {self.kind.name: None, **{name: partial(mode_starter, mode=name) for name in modes()}}

    def parse(self, ctx, data: dict, cell) -> StationSection | None:
        standalone = any(kind.section.standalone(data) for kind in cell.kinds.values())
        return parse(ctx, data, cell, standalone)

    def check(self, ctx, cell) -> None:
        for i, station in enumerate(stations_of(cell)):
            modes()[station.mode].check_station(ctx, f"station[{i}]", station, cell)
            if station.part is not None:
                check_carried(ctx, cell.robot, station.part.mass_kg, f"station[{i}].part.mass_kg")
        if stations_of(cell) and cell.robot is not None:
            _shift_within_reach(ctx, section_of(cell).limits.max_shift_mm, cell.robot.arms)

    def json_schema(self, schema: dict) -> None:
        """A station's mode's keys (required by its mode, refused by the others'), and [cell.camera] and
        [cell.limits] with [[station]]."""
        station = schema["properties"][NAME]["items"]
        own = {name: mode.station_keys() for name, mode in modes().items()}
        first = next(iter(own))
        rules = []
        for name, keys in own.items():
            others = {k: False for m, ks in own.items() if m != name for k in ks if k not in keys}
            condition: dict = {"properties": {"mode": {"enum": [name]}}}
            if name != first:  # the default mode
                condition["required"] = ["mode"]
            then: dict = {"properties": others}
            required = [k for k, key in keys.items() if key.required]
            if required:
                then["required"] = required
            rules.append({"if": condition, "then": then})
        station["allOf"] = rules
        schema["allOf"] = [
            {"if": {"required": [NAME]}, "then": {"properties": {"cell": {"required": list(VISION_TABLES)}}}}
        ]
