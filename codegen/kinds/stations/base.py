"""The base of the station kinds: the [[station]] hooks every kind of the cell's station program provides."""

from __future__ import annotations

import random
from dataclasses import replace
from typing import Any, ClassVar

from codegen.guard import halt_message
from codegen.kinds.stations import judge
from codegen.kinds.stations.cases import Case, build_cases, describe_case, edge_cell, edge_only_cell
from codegen.kinds.stations.envelope import check
from codegen.kinds.stations.program import station_program
from codegen.protocol import ProgramKind, station_kinds


class StationKind(ProgramKind):
    """A kind whose [[station]] tables (`mode = "<name>"`) share the cell's station program: a station's spec,
    its partial templates/<t>/kinds/<name>.j2 in that program, its float64 reference, its verify cases and its
    report figures. Nothing outside a kind's package names its spec or case."""

    station_mode = True

    # The parts of the cell model the kind's programs depend on; the model-level mutation tests
    # perturb each one ("angle_sign", "calibration", "derivation") and verify must notice.
    model_inputs: ClassVar[frozenset[str]] = frozenset()
    log_prefixes: ClassVar[tuple[str, ...]] = ()  # the program's log lines whose numbers verify reads
    log_names: ClassVar[tuple[str, ...]] = ()  # those numbers, in order

    # --- cell file -------------------------------------------------------------------------
    @classmethod
    def parse(cls, ctx, raw: dict, path: str, pose_format: str):
        """The station's spec from its [[station]] table (ctx: codegen.model.validate helpers)."""
        raise NotImplementedError

    @classmethod
    def scene(cls, cell) -> list[dict]:
        """The kind's stations in the cell's page (station_scene of each)."""
        return [o for station in cell.stations if station.kind == cls.name for o in cls.station_scene(cell, station)]

    @classmethod
    def station_scene(cls, cell, station) -> list[dict]:
        """One of the kind's stations in the cell's page (codegen.view.scene's vocabulary)."""
        return []

    @classmethod
    def halt_message(cls, cell, reason: str, station) -> str:
        """The operator message for a halt of one of the kind's stations (a contract)."""
        return halt_message(cell, reason, station.name, station.id)

    @classmethod
    def fitted_message(cls, cell, reason: str, station, limit: int) -> str:
        """The halt message within a controller's string limit: the station's name is shortened, not
        the end of the message, so the operator can still tell the reasons apart."""
        text = cls.halt_message(cell, reason, station)
        if len(text) <= limit:
            return text
        over = len(text) - limit + 3
        short = replace(station, name=station.name[: max(1, len(station.name) - over)] + "...")
        return cls.halt_message(cell, reason, short)

    @classmethod
    def check_station(cls, ctx, path: str, station, cell) -> None:
        """Checks that need the whole cell (e.g. a calibration the kind reads)."""

    @classmethod
    def moved(cls, spec, mm: float):
        """The spec with its calibration moved by `mm` along the base x axis (the mutation tests of a
        kind whose model_inputs include "calibration")."""
        return spec

    # --- the station program ---------------------------------------------------------------
    @classmethod
    def programs(cls, cell, target) -> list:
        """The station program, written once for all station kinds: by the first of the registry."""
        if not cell.stations or not cls.leads(cell):
            return []
        return station_program(cell, target, list(station_kinds().values()), cls.name)

    @classmethod
    def reach(cls, cell, targets: list[str]) -> list:
        """The stations' envelope check (every taught pose over the correction region), once: by the first."""
        if not cell.stations or not cls.leads(cell):
            return []
        return check(cell, targets)

    @classmethod
    def leads(cls, cell) -> bool:
        """Whether this kind speaks for the cell's station program: the first of the registry's station kinds
        that the cell's stations use (its programs are that kind's in verify and the report)."""
        used = {station.kind for station in cell.stations}
        return cls is next((k for k in station_kinds().values() if k.name in used), None)

    # --- verify: the station program's cases, judged (the first station kind's program) ---------------
    report_key = "targets"  # verify's JSON: the station program's rows
    scenarios = {  # codegen.verify.plan.SCENARIOS: every one runs (kinds/stations/cases.py SCENARIO_OF)
        "start_away": "",
        "start_mid_cycle": "",
        "gripper_silent": "",
        "gripper_stuck": "",
        "device_late": "",
        "device_silent": "",
        "reading_out_of_range": "",
    }

    @classmethod
    def verify_models(cls, cell) -> list:
        """The cell; without an arm, the cell with an extra station of edge-case poses (the pose conventions'
        edges); with one, the edge poses as a cell of their own without the arm, beside it (no arm need reach
        them). The edge programs count in the station program's row."""
        if not cell.stations or not cls.leads(cell):
            return []
        if cell.robot is None:
            return [(edge_cell(cell), True)]
        edge = edge_only_cell(cell)
        return [(cell, True)] + ([] if edge is None else [(edge, False)])

    @classmethod
    def verify_cases(cls, cell, source, count: int, seed: int) -> list:
        return build_cases(cell, count, seed)

    @classmethod
    def sweeps(cls, cell, source, workers: int) -> list[range]:
        return judge.sweeps(workers) if source.sweep else []

    @classmethod
    def sweep(cls, cell, source, program, ids: range, step_limit: int, row) -> None:
        judge.sweep(cell, source.target, program, ids, step_limit, row)

    @classmethod
    def setup(cls, cell, source, case):
        return judge.setup(cell, source.target, case)

    @classmethod
    def judge(cls, cell, source, case, trace, setup):
        return judge.judge(cell, source.target, case, trace)

    @classmethod
    def log_prefixes_of(cls, cell) -> tuple[str, ...]:
        return judge.log_prefixes()

    @classmethod
    def describe(cls, cell, case) -> str:
        return describe_case(cell, case.reading)

    @classmethod
    def new_figures(cls):
        return judge.new_figures() or None

    @classmethod
    def add_figures(cls, figures, case, judged) -> None:
        judge.add_figures(figures, judged)

    @classmethod
    def merge_figures(cls, into, part) -> None:
        judge.merge_figures(into, part)

    @classmethod
    def summary(cls, row) -> dict:
        """Each station kind's own figures under its name."""
        out = {}
        for name, kind in station_kinds().items():
            stats = None if row.figures is None else row.figures.get(name)
            own = kind.stats_summary(kind.new_stats() if stats is None else stats)
            if own is not None:
                out[name] = own
        return out

    @classmethod
    def legacy_summary(cls, row) -> dict:
        out = row.summary()
        out["unknown_ids_checked"] = row.swept
        return out

    @classmethod
    def report_lines(cls, rows: list) -> list[str]:
        summaries = [cls.legacy_summary(row) for row in rows]
        out = []
        for kind in station_kinds().values():  # each kind's own figures, as a table of its own
            out.extend(kind.stats_lines(summaries))
        swept = sum(row.swept for row in rows)
        if swept:
            out.append(f"{swept} runs of the other station ids (each id that is not a station must stop before moving)")
        return out

    # --- rendering -------------------------------------------------------------------------
    @classmethod
    def cell_context(cls, cell, target, emitter) -> dict:
        """Template variables of the kind, shared by its stations."""
        return {}

    @classmethod
    def station_context(cls, cell, station, target, emitter) -> dict:
        """Template variables of one station of this kind."""
        return {}

    # --- the arm -----------------------------------------------------------------------------
    @classmethod
    def arm_poses(cls, cell, station) -> list[tuple[str, Any, str]]:
        """The poses the arm visits in a station, in order: (pose name, tcp2base at calibration,
        "joint" or "linear"). Each has one configuration in the program (codegen/robot/)."""
        return [(p.name, p.matrix(), "joint" if i == 0 else "linear") for i, p in enumerate(station.path)]

    @classmethod
    def region(cls, cell, station, offsets) -> Any:
        """Every arm pose corrected by every reading the guard lets through: offsets is (N, 3) of
        (dx mm, dy mm, rotation deg) over the cell's limits; returns (N, len(arm_poses), 4, 4) tcp2base."""
        raise NotImplementedError

    # --- reference and verify --------------------------------------------------------------
    @classmethod
    def cases(cls, cell, station, count: int, rng: random.Random) -> list[Case]:
        raise NotImplementedError

    @classmethod
    def nominal_case(cls, cell, station) -> Case:
        """The case in which nothing moved since calibration: the program visits the taught poses."""
        raise NotImplementedError

    @classmethod
    def edge_spec(cls):
        """A spec for verify's extra station of edge-case poses, or None if the kind has none."""
        return None

    @classmethod
    def accepted(cls, cell, reading) -> tuple[list, bool]:
        """The reference traces a correct program may produce, and whether the case is on a boundary."""
        raise NotImplementedError

    @classmethod
    def truth_problem(cls, cell, reading, reference) -> str | None:
        """Where the case's physical situation (its simulated devices) demands something the cell's
        own reference does not do, what: then the cell contradicts its devices (e.g. a camera sign)
        and every target's run of the case is a mismatch. None: nothing to say."""
        return None

    @classmethod
    def answer(cls, cell, target, reading) -> dict:
        """What the vision PC answers the program's request to read the station (codegen.model.vision.READ),
        by the program's names (the --input names): the station id, and what else the kind reads."""
        return {target.program["inputs"]["station"]: reading.station_id}

    @classmethod
    def second_look(cls, reading):
        """The reading of a second answer to the same request (codegen.model.vision "twice"), or None when the
        kind's answer does not change: a program that uses it whole moves correctly for it too."""
        return None

    @classmethod
    def previous(cls, cell, target, station) -> dict:
        """What the vision PC's variables hold from the previous cycle when the program starts: a
        plausible reading of the station (a program that does not wait for its answer uses it)."""
        return {target.program["inputs"]["station"]: station.id}

    @classmethod
    def inputs(cls, cell, target, reading) -> dict:
        """Values the controller holds when the program starts besides the vision PC's (--input names)."""
        return {}

    @classmethod
    def camera(cls, cell, reading):
        """The simulated camera the vision PC photographs with for this case (None: the kind takes no photos)."""
        return None

    @classmethod
    def describe_reading(cls, reading) -> str:
        return f"station {reading.station_id}"

    @classmethod
    def new_stats(cls) -> Any:
        """The kind's own report figures (None: it has none)."""
        return None

    @classmethod
    def add_stats(cls, stats, reading, logged: list[float]) -> None:
        """Add a passing case's logged numbers to the figures."""

    @classmethod
    def merge_stats(cls, into, part) -> None:
        """Add the figures of another chunk of cases."""

    @classmethod
    def stats_summary(cls, stats) -> dict | None:
        return None

    @classmethod
    def stats_lines(cls, summaries: list[dict]) -> list[str]:
        """The kind's figures as text lines for the `codegen verify` report (summaries: per target)."""
        return []
