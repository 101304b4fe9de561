"""Every configuration a bundled pallet program (and the demo's station program) names in full holds a margin away
from its boundaries: no Turn bit or quadrant there is decided by rounding (the controller computes the same field).
A station pose may still name one at a boundary where the controller's own rule without it would turn an axis one
way for some readings and the other way for others (codegen/kinds/station/region.py): the thermometer bench's
bath photo, which is therefore not among these cells."""

from __future__ import annotations

import numpy as np
import pytest

from codegen.dialects.core.arm import ArmState
from codegen.model.cell import EXAMPLES_DIR, load_cell
from codegen.robot.config import FORMS, ROUNDING_MARGIN_DEG
from codegen.verify.engine import Options, verify_cell

CELLS = ("agv_machine_tending.toml", "pallets/eur_pallet.toml", "pallets/testmat_pallet.toml")
FAST = Options(cases=1, jobs=1, sweeps=False)


def _distance_to_boundary(form: str, joints: np.ndarray) -> float:
    """How far the axes a form's fields depend on lie from the nearest boundary, by the manuals' definitions
    (written out here, not through codegen's configuration code): KUKA Turn bit i is axis i+1's sign; ABB's
    cf1, cf4, cf6 are the quadrants floor(angle / 90) of axes 1, 4 and 6."""
    if form == "status_turn":
        return float(np.min(np.abs(joints)))
    quarters = joints[[0, 3, 5]] / 90.0
    return float(np.min(np.abs(quarters - np.round(quarters))) * 90.0)


@pytest.mark.slow  # a whole verify run: in the slow set (the default run stays near 5 minutes)
@pytest.mark.parametrize("name", CELLS)
@pytest.mark.parametrize("target", ["kuka", "abb"])
def test_a_full_configuration_is_named_only_away_from_its_boundaries(monkeypatch, name, target):
    cell = load_cell(EXAMPLES_DIR / name)
    if target not in cell.targets:
        pytest.skip(f"{name} has no {target} program")
    named: list[tuple[str, str, np.ndarray]] = []
    rules: set[str] = set()
    select = ArmState._select

    def recording(self, p, sols):
        q, branch = select(self, p, sols)
        rules.add(p.rule)
        if p.rule in FORMS and not FORMS[p.rule].exact:
            named.append((p.rule, p.where, np.asarray(q, dtype=float)))
        return q, branch

    monkeypatch.setattr(ArmState, "_select", recording)
    report = verify_cell(cell, (), (target,), FAST)
    assert report.ok
    assert rules - {"keep"}, "no joint move to a pose ran: the check saw nothing"
    if not named:
        return  # every joint move leaves the configuration to the controller's rule (none named in full)
    worst = min(named, key=lambda item: _distance_to_boundary(item[0], item[2]))
    distance = _distance_to_boundary(worst[0], worst[2])
    where, joints = worst[1], np.round(worst[2], 6).tolist()
    assert distance >= ROUNDING_MARGIN_DEG, (
        f"{where}: joints {joints} name a field {distance:.2e} deg from its boundary"
    )
