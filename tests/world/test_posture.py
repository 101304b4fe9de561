"""The posture generate chooses where the cell names none: verify holds the program to it (a UR program steered to
the elbow-down solution fails), and the choice keeps the nearest-home posture where nothing clears by more."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from support.cells import EXAMPLES
from test_generate_clearance import UR5E_FRONT, _elbow_z, _nearest

from codegen.generate import GenerateError, check_clearance, check_envelope, generate
from codegen.model.cell import load_cell
from codegen.render import joints_literal
from codegen.verify.engine import Options, verify_cell


def test_verify_holds_the_ur5e_program_to_the_chosen_posture(tmp_path):
    """The UR5e cell facing away from its station, generated elbow up: its program passes verify; the same program
    with get_inverse_kin steered to the posture nearest the home (the elbow under the work) fails it."""
    path = tmp_path / "ur5e_front.toml"
    path.write_text(UR5E_FRONT.format(home=""), encoding="utf-8")
    cell = load_cell(path)
    arm = cell.robot.arms["ur"]
    written, _, _ = generate(cell, ["ur"], tmp_path / "out")
    scripts = sorted(str(p) for p in written if p.suffix == ".script")
    options = Options(cases=4, seed=3, jobs=1, sweeps=False)
    assert verify_cell(cell, scripts, ("ur",), options).ok
    press = next(iter(cell.sections["station"].stations))
    approach = cell.kinds["station"].scene.paths(cell, ["ur"])[0].moves[0].joints
    assert _elbow_z(arm, approach) > 180.0
    flange = press.poses[0].matrix() @ np.linalg.inv(cell.robot.tool.tcp2flange)
    low = _nearest(arm.kin.ik(flange), cell.robot.home["ur"])
    assert _elbow_z(arm, low) < _elbow_z(arm, approach)  # another solution of the same pose
    chosen = "qnear=[" + ", ".join(str(v) for v in joints_literal(approach, "rad")) + "]"
    other = "qnear=[" + ", ".join(str(v) for v in joints_literal(low, "rad")) + "]"
    for script in map(Path, scripts):
        text = script.read_text(encoding="utf-8")
        assert text.count(chosen) == 1
        script.write_text(text.replace(chosen, other), encoding="utf-8")
    report = verify_cell(cell, scripts, ("ur",), options)
    assert not report.ok
    said = " ".join(m for row in report.rows for m in row.first_mismatches)
    assert "move 2 (approach, line" in said and "the controller's rule gives" in said


def test_generate_reports_a_posture_it_chose_and_none_where_the_home_gives_it(tmp_path):
    """generate's report names the posture chosen for the UR5e facing away from its station (in the target's own form,
    the joints) and why; the demo cell's stations keep the posture nearest the home, and say nothing."""
    path = tmp_path / "ur5e_front.toml"
    path.write_text(UR5E_FRONT.format(home=""), encoding="utf-8")
    cell = load_cell(path)
    (envelope,) = check_envelope(cell, ["ur"])
    approach = cell.kinds["station"].scene.paths(cell, ["ur"])[0].moves[0].joints
    shown = ", ".join(f"{v:.6g}" for v in approach)
    said = envelope.text()
    assert f"posture chosen to clear the cell: pose 'approach' in configuration [{shown}] (joints), least" in said
    assert "the configuration nearest the home does not clear" in envelope.text()
    (demo,) = check_envelope(load_cell(EXAMPLES["agv_machine_tending"]), ["ur"])
    assert "posture" not in demo.text() and all(s["posture"] == "" for s in demo.as_json()["stations"])


def test_the_ur5e_posture_is_the_one_nearest_the_home_of_those_that_clear(tmp_path):
    """Each solution of the approach (the UR5e's 8 branches, each axis turned nearest the home) named in the cell
    ([station.config.ur], so nothing is chosen) and proven by generate: of those that clear, all equally (the tool
    over the bed sets their least clearance), the chosen posture is the one nearest the home."""
    path = tmp_path / "ur5e_front.toml"
    path.write_text(UR5E_FRONT.format(home=""), encoding="utf-8")
    cell = load_cell(path)
    arm, home = cell.robot.arms["ur"], np.asarray(cell.robot.home["ur"])
    press = next(iter(cell.sections["station"].stations))
    solutions = arm.kin.ik(press.poses[0].matrix() @ np.linalg.inv(cell.robot.tool.tcp2flange))
    clear = {}
    for q in solutions[~np.isnan(solutions).any(axis=1)]:
        q = q + 360.0 * np.round((home - q) / 360.0)
        named = f"[station.config.ur]\napproach = [{', '.join(f'{v:.9f}' for v in q)}]\n"
        path.write_text(UR5E_FRONT.format(home="") + named, encoding="utf-8")
        try:
            least = min(x.found.distance for x in check_clearance(load_cell(path), ["ur"]))
        except GenerateError:
            continue
        clear[float(np.linalg.norm(q - home))] = (q, least)
    assert len(clear) >= 2
    leasts = [least for _, least in clear.values()]
    assert max(leasts) - min(leasts) < 1.0  # equally clear: the nearest the home is kept
    expected = clear[min(clear)][0]
    path.write_text(UR5E_FRONT.format(home=""), encoding="utf-8")
    chosen = load_cell(path)
    approach = chosen.kinds["station"].scene.paths(chosen, ["ur"])[0].moves[0].joints
    np.testing.assert_allclose(approach, expected, atol=1e-6)


def test_generate_takes_the_station_paths_as_the_posture_choice_proved_them(tmp_path, monkeypatch):
    """The UR5e's posture was chosen by proving its paths at every proven reading (the plan keeps the least clearances):
    generate's clearance proof proves none of them again, and its least clearances are those of a proof of the same
    paths made here."""
    from codegen import generate as generating
    from codegen.world import proof

    path = tmp_path / "ur5e_front.toml"
    path.write_text(UR5E_FRONT.format(home=""), encoding="utf-8")
    cell = load_cell(path)
    kind = cell.kinds["station"]
    paths = kind.scene.paths(cell, ["ur"])
    assert paths and all(s.proven is not None and s.note for s in kind.plan(cell, "ur").stations)
    fresh = proof.prove(cell, paths)
    real, proved = proof.prove, []

    def counted(cell, paths, *args, **kwargs):
        proved.extend(paths)
        return real(cell, paths, *args, **kwargs)

    monkeypatch.setattr(proof, "prove", counted)
    least = generating._proven(cell, "ur")
    assert proved == []  # no path proven a second time
    assert [(x.where, x.found.distance) for x in least] == [(x.where, x.found.distance) for x in fresh]
