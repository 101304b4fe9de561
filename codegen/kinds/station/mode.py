"""A station mode: how one [[station]] table (`mode = "<name>"`) reads, moves, is judged; the modes' registry."""

from __future__ import annotations

import importlib
import pkgutil
import random
from dataclasses import replace
from functools import cache
from typing import Any, ClassVar

from codegen.guard import halt_message


class StationMode:
    """One mode of the station kind (its module in codegen/kinds/station/modes/ registers it): a station's spec
    from its [[station]] keys, its partial templates/<t>/kinds/station_<mode>.j2 of the station program, its
    float64 reference, its verify cases and its report figures. Nothing outside its module names it."""

    name: ClassVar[str] = ""  # the cell file's `mode`; "" for an abstract base: not registered
    order: ClassVar[int] = 100  # where the mode comes in the program and the reports, lowest first
    # the mode's part of the cell file (codegen.model.schema.KindKeys): its [[station]] keys, its [cell.<name>]
    cell_file: ClassVar[Any] = None
    # The parts of the cell model the mode's programs depend on; the model-level mutation tests
    # perturb each one ("angle_sign", "calibration", "derivation") and verify must notice.
    model_inputs: ClassVar[frozenset[str]] = frozenset()
    log_prefixes: ClassVar[tuple[str, ...]] = ()  # the program's log lines whose numbers verify reads
    log_names: ClassVar[tuple[str, ...]] = ()  # those numbers, in order
    reads_pixels: ClassVar[bool] = False  # the camera answers in pixels: the cell needs [cell.camera.handeye]
    # the values (protocol names, codegen.model.vision) the mode's stations read from an answer, by command
    answer_names: ClassVar[dict[int, tuple[str, ...]]] = {}
    # the mode's own report figures (codegen.protocol.Figures: count(reading, logged numbers)); None: it has none
    figures: ClassVar[type | None] = None
    registry: ClassVar[dict[str, type[StationMode]]] = {}

    def __init_subclass__(cls, **kwargs) -> None:
        super().__init_subclass__(**kwargs)
        if cls.name:
            StationMode.registry[cls.name] = cls

    @classmethod
    def station_keys(cls) -> dict:
        return {} if cls.cell_file is None else cls.cell_file.station_keys

    # --- cell file -------------------------------------------------------------------------
    @classmethod
    def parse(cls, ctx, values: dict, path: str):
        """The station's spec from its [[station]] table as the loader read it (values: each key's, by its declaration
        in station_keys(); ctx: codegen.model.validate helpers): the rules between the keys."""
        raise NotImplementedError

    @classmethod
    def parse_settings(cls, ctx, cell_table: dict):
        """The mode's settings from its [cell.<name>] tables (kept in the section's settings[mode name])."""
        return None

    @classmethod
    def check_station(cls, ctx, path: str, station, cell) -> None:
        """Checks that need the whole cell (e.g. a calibration the mode reads)."""

    @classmethod
    def moved(cls, spec, mm: float):
        """The spec with its calibration moved by `mm` along the base x axis (the mutation tests of a
        mode whose model_inputs include "calibration")."""
        return spec

    @classmethod
    def commands(cls) -> list:
        """The mode's click commands: (the group they belong to, or None, command)."""
        return []

    # --- the cell's page ---------------------------------------------------------------------
    @classmethod
    def station_scene(cls, cell, station) -> list[dict]:
        """One of the mode's stations in the cell's page (codegen.view.scene's vocabulary)."""
        return []

    # --- messages --------------------------------------------------------------------------
    @classmethod
    def halt_message(cls, cell, reason: str, station) -> str:
        """The operator message for a halt of one of the mode's stations (a contract)."""
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

    # --- rendering -------------------------------------------------------------------------
    @classmethod
    def cell_context(cls, cell, target, emitter) -> dict:
        """Template variables of the mode, shared by its stations."""
        return {}

    @classmethod
    def station_context(cls, cell, station, target, emitter) -> dict:
        """Template variables of one station of this mode."""
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
    def cases(cls, cell, station, count: int, rng: random.Random) -> list:
        raise NotImplementedError

    @classmethod
    def nominal_case(cls, cell, station):
        """The case in which nothing moved since calibration: the program visits the taught poses."""
        raise NotImplementedError

    @classmethod
    def edge_spec(cls):
        """A spec for verify's extra station of edge-case poses, or None if the mode has none."""
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
        by the program's names (the --input names): the station id, and what else the mode reads."""
        return {target.program["inputs"]["station"]: reading.station_id}

    @classmethod
    def second_look(cls, reading):
        """The reading of a second answer to the same request (codegen.model.vision "twice"), or None when the
        mode's answer does not change: a program that uses it whole moves correctly for it too."""
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
        """The simulated camera the vision PC photographs with for this case (None: the mode takes no photos)."""
        return None

    @classmethod
    def describe_reading(cls, reading) -> str:
        return f"station {reading.station_id}"

    # --- report figures --------------------------------------------------------------------
    @classmethod
    def stats_lines(cls, summaries: list[dict]) -> list[str]:
        """The mode's figures as text lines for the `codegen verify` report (summaries: per target)."""
        return []


@cache
def modes() -> dict[str, type[StationMode]]:
    """Every module of codegen/kinds/station/modes/ (found, not named: each registers its mode when imported), in
    the order of `order` then by name."""
    package = importlib.import_module("codegen.kinds.station.modes")
    for info in pkgutil.iter_modules(package.__path__):
        importlib.import_module(f"codegen.kinds.station.modes.{info.name}")
    registered = StationMode.registry
    return {name: registered[name] for name in sorted(registered, key=lambda n: (registered[n].order, n))}


def get_mode(name: str) -> type[StationMode]:
    return modes()[name]


def mode_of(station) -> type[StationMode]:
    """The mode of a station (its `mode` key)."""
    return modes()[station.mode]
