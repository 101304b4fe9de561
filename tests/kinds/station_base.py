"""One test base for the station program of every controller target: each target's tests are a subclass naming it."""

from __future__ import annotations

import re
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from lark import Token
from support import stations
from support.cells import EXAMPLES, HOSTILE, cell_text, example, is_configuration, replace_once, structure

from codegen import derived
from codegen.controllers import get_target
from codegen.dialects import get_dialect, parse_program
from codegen.kinds.station.keys import STATION_ID_MAX
from codegen.kinds.station.mode import mode_of
from codegen.kinds.station.section import section_of, stations_of, with_section
from codegen.model.cell import load_cell
from codegen.reference import home_move
from codegen.render import render

STATION_CELLS = [name for name in EXAMPLES if stations_of(example(name))]
# a model mutation -> the model input it changes (a station mode depends on it where its model_inputs name it)
MODEL_NEEDS = {"angle_sign_flipped": "angle_sign", "calibration_moved_0_05mm": "calibration"}
MODEL_NEEDS["sin_cos_swapped"] = "derivation"


def _modes_hit(cell, mutation: str) -> set[str]:
    """The station modes of the cell whose programs depend on what the mutation changes."""
    return {s.mode for s in stations_of(cell) if MODEL_NEEDS[mutation] in mode_of(s).model_inputs}


# (station cell, model mutation) where some station mode of the cell depends on what the mutation changes
MODEL_MUTATIONS = [(name, m) for name in STATION_CELLS for m in MODEL_NEEDS if _modes_hit(example(name), m)]
MUTATION_IDS = [f"{name}-{mutation}" for name, mutation in MODEL_MUTATIONS]


def _swap_sin_cos(dialect: str):
    """derived.printed with the dialect's sin and cos exchanged in every printed block."""
    table = get_dialect(dialect).printer().known_functions
    sin, cos = table["sin"], table["cos"]
    original = derived.printed

    def swap(code: str) -> str:
        return re.sub(rf"\b({sin}|{cos})\(", lambda m: (cos if m.group(1) == sin else sin) + "(", code)

    def printed(name: str, block: str) -> dict:
        code = original(name, block)
        if name != dialect:
            return code
        return {
            "temps": [[t, swap(c)] for t, c in code["temps"]],
            "outputs": {k: swap(c) for k, c in code["outputs"].items()},
        }

    return printed


class StationTests:
    """Subclasses set `target`; every test below then runs the station program of that controller, on every example
    cell with stations, and on model-level mutations each station kind gets for free."""

    target: str

    @pytest.fixture(scope="class", params=STATION_CELLS)
    @classmethod
    def cell(cls, request):
        return example(request.param)

    def test_facts_have_sources(self):
        assert get_target(self.target).sources, "each target cites where its facts come from"

    def test_every_station_id_runs_its_own_station(self, cell):
        """Run each station's id with its kind's zero-offset case: the first move is that station's."""
        program = stations.source(cell, self.target).load()
        for station in stations_of(cell):
            case = mode_of(station).nominal_case(cell, station)
            got = stations.run(cell, self.target, program, case)
            (want, *_), _ = mode_of(station).accepted(cell, case.reading)
            assert not got.halted, (station.name, got.halt_message)
            first = 0 if home_move(cell, self.target) is None else 1  # after the home move
            assert len(got.moves) > first, station.name
            assert np.allclose(got.moves[first].tcp2base, want.moves[0].tcp2base, atol=1e-2), station.name

    def test_identifiers_within_limit(self, tmp_path):
        target = get_target(self.target)
        long_name = "station_with_a_really_long_descriptive_name_" * 4
        path = tmp_path / "cell.toml"
        path.write_text(cell_text([long_name, long_name + "2"]), encoding="utf-8")
        files = render(load_cell(path), [self.target])
        for f in (f for f in files if not is_configuration(f.relpath)):  # a channel's XML names no identifier
            tree = parse_program(f.relpath, f.text)
            for token in tree.scan_values(lambda t: isinstance(t, Token) and t.type == "NAME"):
                assert len(token) <= target.identifier_max, token

    def test_collision_after_mapping_is_an_error(self, tmp_path):
        from codegen.emit import EmitError

        path = tmp_path / "cell.toml"
        path.write_text(cell_text(["lathe 1", "lathe-1"]), encoding="utf-8")
        with pytest.raises(EmitError, match="both map to the identifier"):
            render(load_cell(path), [self.target])

    # The test reads only the class's `target`, so running it from each subclass is sound.
    @settings(
        max_examples=25,
        deadline=None,
        suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.differing_executors],
    )
    @pytest.mark.slow
    @given(a=HOSTILE, b=HOSTILE, pose=HOSTILE)
    def test_hostile_names_cannot_change_the_program_structure(self, tmp_path_factory, a, b, pose):
        folder = tmp_path_factory.mktemp("hostile")
        benign, hostile = folder / "benign.toml", folder / "hostile.toml"
        benign.write_text(cell_text(["s_one", "s_two"], ["approach", "work"]), encoding="utf-8")
        hostile.write_text(cell_text([a + "1", b + "2"], [pose + "1", pose + "2"]), encoding="utf-8")
        if pose + "1" == pose + "2":
            return
        expected = [structure(f.relpath, f.text) for f in render(load_cell(benign), [self.target])]
        got_files = render(load_cell(hostile), [self.target])
        got = [structure(f.relpath, f.text) for f in got_files]
        assert got == expected
        limit = get_target(self.target).string_max
        for f in got_files:
            for literal in re.findall(r'"([^"\n]*)"', f.text):
                assert len(literal) <= limit + 2  # + format placeholders appended by the template

    def test_verify_passes(self, cell):
        report = stations.verify(cell, stations.source(cell, self.target), stations.build_cases(cell, 20, 3))
        assert report.mismatches == 0, report.first_mismatches
        assert report.moves > 0 and report.halts > 0

    @pytest.mark.parametrize(("cell", "mutation"), MODEL_MUTATIONS, indirect=["cell"], ids=MUTATION_IDS)
    def test_model_mutations_fail_verify(self, cell, mutation, monkeypatch):
        """Render from a perturbed model, verify against the true cell: every kind must see each one (each cell with
        the mutations some station mode of it depends on: MODEL_MUTATIONS)."""
        kinds_hit = _modes_hit(cell, mutation)
        assert kinds_hit
        mutant = cell
        if mutation == "angle_sign_flipped":
            mutant = with_section(cell, angle_sign=-section_of(cell).angle_sign)
        elif mutation == "calibration_moved_0_05mm":
            moved = tuple(replace(s, spec=mode_of(s).moved(s.spec, 0.05)) for s in stations_of(cell))
            mutant = with_section(cell, stations=moved)
        else:
            monkeypatch.setattr(derived, "printed", _swap_sin_cos(get_target(self.target).dialect))
        text, dat = stations.files(mutant, self.target)
        monkeypatch.undo()
        assert (text, dat) != stations.files(cell, self.target), f"{mutation} changed nothing"
        program = stations.source(cell, self.target, text, dat)
        cases = stations.build_cases(cell, 8, 4)
        kind_of = {station.id: station.mode for station in stations_of(cell)}
        for kind in kinds_hit:  # each kind on its own: one must not hide another
            mine = [c for c in cases if kind_of.get(c.reading.station_id) == kind]
            report = stations.verify(cell, program, mine, first=True)
            assert report.mismatches > 0, f"verify missed {mutation} in the {kind} stations"

    @pytest.mark.parametrize("mutation", ["swap_sin_cos", "flip_sign", "drop_guard", "calibration_number"])
    def test_text_mutations_fail_verify(self, mutation):
        """Careless edits of the demo program's text (each target names its own)."""
        cell = example("agv_machine_tending")
        text, dat = stations.files(cell, self.target)
        program = self.mutant(mutation, text, dat)
        report = stations.verify(cell, program, stations.build_cases(cell, 10, 4), first=True)
        assert report.mismatches > 0, f"verify missed the mutation {mutation}"

    @pytest.mark.slow
    def test_an_extra_dispatch_id_anywhere_in_the_range_is_caught(self):
        """A misread barcode must not move the robot: the sweep of every id finds one extra branch."""
        cell = example("agv_machine_tending")
        text, dat = stations.files(cell, self.target)
        program = self.mutant("extra_dispatch_id", text, dat)
        report = stations.sweep(cell, program, range(STATION_ID_MAX + 1))  # what `codegen verify CELL FILE` sweeps
        assert report.mismatches == 1 and report.swept == STATION_ID_MAX + 1 - len(stations_of(cell))
        assert "unknown station id 20000" in report.first_mismatches[0]
        caught = stations.sweep(cell, program, range(19990, 20010))
        assert caught.mismatches == 1 and "unknown station id 20000" in caught.first_mismatches[0]
        clean = stations.sweep(cell, stations.source(cell, self.target), range(19990, 20010))
        assert clean.mismatches == 0 and clean.swept == 20

    def mutate(self, mutation: str, text: str, dat: str | None):
        raise NotImplementedError

    def mutant(self, mutation: str, text: str, dat: str | None):
        """The station program with the target's edit `mutation` (self.mutate), as a source to verify."""
        mutated = self.mutate(mutation, text, dat)
        new_text, new_dat = mutated if isinstance(mutated, tuple) else (mutated, dat)
        assert (new_text, new_dat) != (text, dat), f"mutation {mutation} changed nothing"
        return stations.source(example("agv_machine_tending"), self.target, new_text, new_dat, mutation)


class MotionTests:
    """For a StationTests subclass whose moves state a speed, zone or base (dtrans's state none)."""

    motion_mutations: list[str]  # how the arm moves: speed, acceleration, zone, base (per target)

    def test_motion_mutations_fail_verify(self):
        """Speed, acceleration, blending on the work pose, the base: changes the pose check cannot see."""
        cell = example("agv_machine_tending")
        text, dat = stations.files(cell, self.target)
        for mutation in self.motion_mutations:
            program = self.mutant(mutation, text, dat)
            report = stations.verify(cell, program, stations.build_cases(cell, 5, 4), first=True)
            assert report.mismatches > 0, f"verify missed {mutation}"


class ArmTests:
    """For a StationTests subclass whose language has a robot model (dtrans's has none)."""

    # Edits only the arm model sees (each target names its own): a configuration changed by hand, the
    # tool or load not set, a pose moved out of reach, a first motion the controller refuses.
    arm_mutations: list[str]

    def test_arm_mutations_fail_verify(self):
        cell = example("agv_machine_tending")
        text, dat = stations.files(cell, self.target)
        cases = [c for c in stations.build_cases(cell, 4, 4) if c.reading.station_id in self.arm_stations]
        for mutation in self.arm_mutations:
            program = self.mutant(mutation, text, dat)
            report = stations.verify(cell, program, cases, first=True)
            assert report.mismatches > 0, f"verify missed {mutation}"
            assert any(word in report.first_mismatches[0] for word in self.arm_words[mutation]), (
                mutation,
                report.first_mismatches[0],
            )

    arm_words: dict[str, tuple[str, ...]]  # what the first mismatch of each arm mutation says
    arm_stations = (1,)  # the demo's stations whose cases the arm mutations run


class HaltGoesOnTests:
    """For a StationTests subclass whose controller resumes after a halt (UR halt and dtrans Halt end the program)."""

    def test_a_halt_the_program_goes_on_from_is_caught(self):
        """Where the controller resumes after a halt (KRL HALT, RAPID Stop), a program that moves
        after the operator's restart must fail verify."""
        cell = example("agv_machine_tending")
        text, dat = stations.files(cell, self.target)
        program = self.mutant("halt_goes_on", text, dat)
        report = stations.verify(cell, program, stations.build_cases(cell, 10, 4))
        before = 0 if home_move(cell, self.target) is None else 1  # the home move comes first
        assert report.mismatches > 0 and any(f"moves, expected {before}" in m for m in report.first_mismatches)


__all__ = ["ArmTests", "HaltGoesOnTests", "MotionTests", "StationTests", "replace_once"]
