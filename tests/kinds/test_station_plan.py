"""The station kind's plan: made once per cell and target, handed down with the cell (a cell made or loaded after
another, even at the same address, gets its own), and gone with its cell."""

from __future__ import annotations

import builtins
import gc
import weakref
from dataclasses import replace

import numpy as np

from codegen.kinds.station.plan import taught_poses
from codegen.kinds.station.section import stations_of, with_section
from codegen.model.cell import DEMO_CELL, Cell, load_cell

DEMO_TEXT = DEMO_CELL.read_text()
HEAD = DEMO_TEXT[: DEMO_TEXT.index("[[station]]")]


def _one_station(chuck_x: float) -> str:
    """The demo's arm section with one lathe station whose chuck stands at chuck_x (mm, base frame)."""
    return (
        f'{HEAD}[[station]]\nid = 1\nname = "lathe"\nmark = [612.4, -285.0, 1.8]\n[station.poses]\n'
        f"approach = [655.0, -120.0, 420.0, 90.0, 0.0, 180.0]\nchuck = [{chuck_x}, -112.3, 305.2, 90.0, 0.0, 180.0]\n"
    )


def _chuck_reached(cell, target: str) -> np.ndarray:
    """Where the tool's tip stands at the plan's taught joints of the chuck (base frame, mm): the forward kinematics."""
    taught, _ = taught_poses(cell, target, stations_of(cell)[0])
    chuck = next(pose for pose in taught if pose.name == "chuck")
    return (cell.robot.arms[target].kin.fk(chuck.joints) @ cell.robot.tool.tcp2flange)[:3, 3]


def test_the_plan_is_made_once_per_cell_and_target(tmp_path):
    path = tmp_path / "one.toml"
    path.write_text(_one_station(738.5), encoding="utf-8")
    cell = load_cell(path)
    kind = cell.kinds["station"]
    kuka = kind.plan(cell, "kuka")
    assert kind.plan(cell, "kuka") is kuka
    assert kind.plan(cell, "abb") is not kuka and kind.plan(cell, "abb").target == "abb"
    assert [p.station.id for p in kuka.stations] == [s.id for s in stations_of(cell)]
    assert kind.plan(cell, "dtrans") is None  # no arm on the target: nothing to plan
    changed = replace(cell, sections=dict(cell.sections))  # another cell: its own plans, none inherited
    assert changed.plans == {} and kind.plan(changed, "kuka") is not kuka


def test_a_cell_made_after_another_at_the_same_address_gets_its_own_plan(tmp_path, monkeypatch):
    """Cells with the chuck moved by a millimetre each, made one after another, the one before dropped, and every cell
    given one address (id() patched: what CPython does when a new cell takes a dropped one's memory): each is planned
    as it is, the chuck's taught joints reaching its own chuck. A store keyed by id() would hand it the dropped cell's
    joints, a millimetre off."""
    real_id = builtins.id
    monkeypatch.setattr(builtins, "id", lambda thing: 1 if isinstance(thing, Cell) else real_id(thing))
    path = tmp_path / "one.toml"
    for i in range(3):
        path.write_text(_one_station(738.5 + i), encoding="utf-8")
        cell = load_cell(path)
        assert id(cell) == 1
        np.testing.assert_allclose(_chuck_reached(cell, "kuka"), [738.5 + i, -112.3, 305.2], atol=1e-6)
        del cell
        gc.collect()
    base = load_cell(path)
    for i in range(1, 3):  # cells made from one by dataclasses.replace
        station = replace(stations_of(base)[0], poses=tuple(_moved(p, i) for p in stations_of(base)[0].poses))
        cell = with_section(base, stations=(station,))
        np.testing.assert_allclose(_chuck_reached(cell, "kuka"), [740.5 + i, -112.3, 305.2], atol=1e-6)


def _moved(pose, dx: float):
    """A taught pose moved by dx mm along the base x (the chuck only)."""
    if pose.name != "chuck":
        return pose
    values = list(pose.values)
    values[0] += dx
    return replace(pose, values=tuple(values))


def test_a_dropped_cell_leaves_nothing_behind(tmp_path):
    """The plan lives on its cell: once the cell is dropped, nothing (no module-level store) keeps it alive."""
    path = tmp_path / "one.toml"
    path.write_text(_one_station(738.5), encoding="utf-8")
    cell = load_cell(path)
    assert cell.kinds["station"].plan(cell, "kuka").stations
    taught_poses(cell, "abb", stations_of(cell)[0])
    gone = weakref.ref(cell)
    del cell
    gc.collect()
    assert gone() is None
