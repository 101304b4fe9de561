"""The station kind: the cell's [[station]] tables and the one program that serves them, each station by its mode."""

from __future__ import annotations

from codegen.kinds.station import judge
from codegen.kinds.station.cases import build_cases, describe_case, edge_cell, edge_only_cell
from codegen.kinds.station.envelope import check
from codegen.kinds.station.keys import NAME, VISION_TABLES, kind_keys
from codegen.kinds.station.mode import modes
from codegen.kinds.station.program import station_program
from codegen.kinds.station.section import parse, stations_of
from codegen.protocol import ProgramKind, kinds


class StationKind(ProgramKind):
    """Stations read by a camera and served by one program per target (source 000's point correction, source 001's
    frame refinement, ...): the section (camera, limits, stations), the program, the envelope proof, the cases and
    their judgement are the kind's; what differs between stations is their mode's (codegen.kinds.station.mode)."""

    name = NAME
    order = 0
    cell_file = kind_keys()
    renamed_copies = True

    # --- cell file -------------------------------------------------------------------------
    @classmethod
    def listed_names(cls) -> tuple[str, ...]:
        return tuple(modes())

    @classmethod
    def parse_section(cls, ctx, data: dict, cell):
        standalone = any(kind.standalone(data) for kind in kinds().values())
        return parse(ctx, data, cell, standalone)

    @classmethod
    def check_cell(cls, ctx, cell) -> None:
        for i, station in enumerate(stations_of(cell), start=1):
            modes()[station.mode].check_station(ctx, f"station[{i}]", station, cell)

    @classmethod
    def json_schema(cls, schema: dict) -> None:
        """A station's mode's keys (required by its mode, refused by the others'), and [cell.camera] and
        [cell.limits] with [[station]]."""
        station = schema["properties"][cls.name]["items"]
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
            {
                "if": {"required": [cls.name]},
                "then": {"properties": {"cell": {"required": list(VISION_TABLES)}}},
            }
        ]

    # --- the station program ---------------------------------------------------------------
    @classmethod
    def programs(cls, cell, target) -> list:
        """The station program: every station of the cell, each by its mode."""
        return station_program(cell, target, cls.name) if stations_of(cell) else []

    @classmethod
    def reach(cls, cell, targets: list[str]) -> list:
        """The stations' envelope check (every taught pose over the correction region)."""
        return check(cell, targets) if stations_of(cell) else []

    # --- derivation ---------------------------------------------------------------------------
    @classmethod
    def derive(cls):
        from codegen.kinds.station import derivation  # sympy: only `codegen derive` asks

        return derivation.derive()

    @classmethod
    def describe_derivation(cls, derived) -> str:
        from codegen.kinds.station import derivation

        return derivation.describe()

    @classmethod
    def identities(cls, check) -> list:
        from codegen.kinds.station import derivation

        return [*derivation.point_identities(check), *derivation.frame_identities(check)]

    @classmethod
    def derivation_symbols(cls) -> dict:
        from codegen.kinds.station import derivation

        return derivation.symbols()

    @classmethod
    def printed_blocks(cls) -> dict:
        from codegen.kinds.station import derivation

        return derivation.printed_blocks()

    # --- verify: the station program's cases, judged ---------------------------------------
    report_key = "targets"  # verify's JSON: the station program's rows
    scenarios = {  # codegen.verify.plan.SCENARIOS: every one runs (kinds/station/cases.py SCENARIO_OF)
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
        if not stations_of(cell):
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
        """Each mode's own figures under its name."""
        out = {}
        for name, mode in modes().items():
            stats = None if row.figures is None else row.figures.get(name)
            own = mode.stats_summary(mode.new_stats() if stats is None else stats)
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
        for mode in modes().values():  # each mode's own figures, as a table of its own
            out.extend(mode.stats_lines(summaries))
        swept = sum(row.swept for row in rows)
        if swept:
            out.append(f"{swept} runs of the other station ids (each id that is not a station must stop before moving)")
        return out

    # --- the cell's page and the command line ------------------------------------------------
    @classmethod
    def scene(cls, cell) -> list[dict]:
        """Each station as its mode draws it."""
        return [o for station in stations_of(cell) for o in modes()[station.mode].station_scene(cell, station)]

    @classmethod
    def commands(cls) -> list:
        return [command for mode in modes().values() for command in mode.commands()]
