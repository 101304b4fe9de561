"""The station kind's plan for a cell on one target: each station's configuration, region and proofs, made once."""

# The program writer, verify's cases and judgement, the reach proof and the scene read this plan (codegen.protocol.
# Kind.plan hands it down with the cell, so a cell made from another starts with none) instead of working the posture
# and the correction region out again.

from __future__ import annotations

import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field, replace

from codegen.kinds.station.envelope import StationMargin, TargetEnvelope, station_margin
from codegen.kinds.station.kind import KIND
from codegen.kinds.station.posture import decide
from codegen.kinds.station.region import StationRegion, offsets, station_region
from codegen.kinds.station.section import Station, section_of, stations_of, with_section
from codegen.model.cell import Cell
from codegen.robot.taught import ArmPose, ReachError

PARALLEL_STATIONS = 50  # from this many stations left to prove, their regions are worked out in parallel processes


@dataclass(frozen=True)
class StationPlan:
    """One station on one target: the station with its configuration on the target handed down (the cell's own or the
    posture chosen for it), the posture note (generate's report; "": the controller's own or the cell's), its arm
    poses over the correction region (None where a taught pose has no solution), its envelope margins (None where the
    reach proof refuses it), the reach proof's refusal ("": none) and the least clearances of its paths where the
    posture's choice proved them at every proven reading (None: generate proves them)."""

    station: Station
    note: str
    region: StationRegion | None
    margin: StationMargin | None
    refusal: str = ""
    proven: tuple | None = None

    def solved(self) -> StationRegion:
        """The station's arm poses over the correction region; ReachError where a taught pose has no solution."""
        if self.region is None:
            raise ReachError(self.refusal)
        return self.region

    def arm(self) -> tuple[list[ArmPose], tuple[bool, ...]]:
        """The taught arm poses and whether the program names each one's full configuration; ReachError where a
        taught pose has no solution."""
        region = self.solved()
        return region.taught, region.named


@dataclass(frozen=True)
class Plan:
    """The station kind's plan for one target: the cell with every station's configuration on the target handed down,
    a StationPlan per [[station]] in the cell file's order, and the readings sampled per station."""

    target: str
    cell: Cell
    stations: tuple[StationPlan, ...]
    samples: int
    by_id: dict = field(init=False, compare=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "by_id", {p.station.id: p for p in self.stations})

    def of(self, station) -> StationPlan:
        """The plan of one of the cell's stations (by its id: the cell's own or the handed-down one)."""
        return self.by_id[station.id]


def plan(cell, target: str) -> Plan | None:
    """The kind's planner: each station's configuration (codegen/kinds/station/posture.py: the cell's own, or a posture
    chosen to clear), then its region and envelope margins where the choice did not work them out already (in parallel
    processes for a large cell); None where the cell has no stations or no arm on the target."""
    stations = stations_of(cell)
    if not stations or cell.robot is None or target not in cell.robot.arms:
        return None
    decided = [decide(cell, target, s) for s in stations]
    handed = with_section(
        cell,
        stations=tuple(replace(s, config={**s.config, target: d[0]}) for s, d in zip(stations, decided, strict=True)),
    )
    left = [s for s, d in zip(stations_of(handed), decided, strict=True) if d[2] is None]
    proofs = dict(zip((s.id for s in left), reach_proofs(handed, target, left), strict=True))
    out = []
    for station, (_config, note, chosen) in zip(stations_of(handed), decided, strict=True):
        if chosen is None:
            region, margin, refusal = proofs[station.id]
            out.append(StationPlan(station, note, region, margin, refusal))
        else:
            region, margin, proven = chosen
            out.append(StationPlan(station, note, region, margin, "", proven))
    limits = section_of(cell).limits
    return Plan(target, handed, tuple(out), len(offsets(limits.max_shift_mm, limits.max_rotation_deg)))


def station_plan(cell, target: str, station) -> StationPlan:
    """The plan of one station of the cell on the target (the kind's plan, made once per cell and target)."""
    return KIND.plan(cell, target).of(station)


def taught_poses(cell, target: str, station) -> tuple[list[ArmPose], tuple[bool, ...]]:
    """The station's taught arm poses on the target and whether the program names each one's full configuration, in
    the configuration handed down (ReachError where a taught pose has no solution)."""
    return station_plan(cell, target, station).arm()


def check(cell, only: list[str] | None = None) -> list[TargetEnvelope]:
    """The envelope check of every target with an arm (of `only`, if given) in the configurations the programs take:
    ReachError naming the first station refused, else each station's margins with the note of a posture chosen to
    clear the cell."""
    if cell.robot is None or not stations_of(cell):  # a cell without stations: its kinds prove their own reach
        return []
    out = []
    for target in [t for t in cell.targets if t in cell.robot.arms and (only is None or t in only)]:
        planned = KIND.plan(cell, target)
        margins = []
        for station in planned.stations:
            if station.refusal:
                raise ReachError(station.refusal)
            margins.append(replace(station.margin, posture=station.note))
        out.append(TargetEnvelope(target, cell.robot.arms[target].model, planned.samples, tuple(margins)))
    return out


def _reach(cell, target: str, station) -> tuple[StationRegion | None, StationMargin | None, str]:
    """The station's region and envelope margins on the target in the configuration the cell gives it, or what refuses
    them."""
    try:
        region = station_region(cell, target, station)
    except ReachError as exc:
        return None, None, str(exc)
    try:
        return region, station_margin(cell, target, station, region), ""
    except ReachError as exc:
        return region, None, str(exc)


_FORKED: dict = {}  # the cell a forked worker proves (inherited, not pickled)


def reach_proofs(cell, target: str, stations: list) -> list[tuple]:
    """_proofs of each station, in order: in forked processes (chunks of stations, spread evenly) from
    PARALLEL_STATIONS stations on where the machine has more than one core (not from a worker process)."""
    workers = os.cpu_count() or 1
    if (
        workers < 2
        or len(stations) < PARALLEL_STATIONS
        or "fork" not in multiprocessing.get_all_start_methods()
        or multiprocessing.parent_process() is not None  # a worker already: its parent spreads the work
    ):
        return [_reach(cell, target, s) for s in stations]
    size = -(-len(stations) // (2 * workers))
    chunks = [(target, tuple(s.id for s in stations[i : i + size])) for i in range(0, len(stations), size)]
    _FORKED["cell"] = cell
    try:
        with ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("fork")) as pool:
            return [found for chunk in pool.map(_reach_forked, chunks) for found in chunk]
    finally:
        _FORKED.clear()


def _reach_forked(task: tuple[str, tuple[int, ...]]) -> list[tuple]:
    target, ids = task
    cell = _FORKED["cell"]
    section = section_of(cell)
    return [_reach(cell, target, section.station_by_id(i)) for i in ids]
