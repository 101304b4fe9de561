"""A teach-pendant program written in KUKA's everyday style (tests/dialects/krl/programs/pickcell: inline-form
folds and their .dat, BAS calls, $config.dat names and signals, a library module, a GOTO, a TRIGGER, a timer,
Windows-1252 text) runs with every move."""

from __future__ import annotations

from pathlib import Path

import pytest

from codegen.dialects.core.files import read_source
from codegen.robot.arms import find_arm

from .helpers import KRL

PICKCELL = Path(__file__).parent / "programs" / "pickcell"


def pickcell():
    texts = [read_source(p, KRL.encodings) for p in sorted(PICKCELL.iterdir())]
    [group] = KRL.programs(texts)
    assert [Path(f.name).name for f in group] == [
        "pickcell.src",
        "pickcell.dat",
        "cellutil.src",
        "cellutil.dat",
        "$config.dat",
    ]
    return KRL.load_files(group)


def test_it_runs_three_parts_with_every_move_and_its_outputs():
    trace = pickcell().run(
        {}, signals={"$IN[17]": True}, arm=find_arm("KR 10 R1100 sixx"), keep=("PARTS_TOTAL", "NPART")
    )
    assert not trace.halted and trace.kept == {"PARTS_TOTAL": 3, "NPART": 3}
    assert len(trace.moves) == 1 + 3 * 5 + 1 and all(m.joints is not None for m in trace.moves)
    assert [m.kind for m in trace.moves[1:6]] == ["joint", "linear", "linear", "joint", "linear"]
    assert trace.moves[2].tcp2base[:3, 3].tolist() == pytest.approx([600.0, -300.0, 220.0])  # BASE_DATA[1], tool
    assert trace.moves[5].tcp2base[:3, 3].tolist() == pytest.approx([400.0, 400.0, 150.0])  # BASE_DATA[2] turned
    assert [o.value for o in trace.outputs] == [True, False, True, False, True, False, True]
    # the TRIGGER: 20 mm before the table, at 0.2 m/s, then the LIN's deceleration at $ACC.CP 2.3 m/s2 (DEF_ACC_CP):
    # 20 mm less the ramp's v^2 / 2a at v, then the ramp in v / a: 0.02 / 0.2 + 0.2 / (2 x 2.3) s before the end
    opened_on_the_way = trace.outputs[2]
    before = 0.02 / 0.2 + 0.2 / (2 * 2.3)
    assert opened_on_the_way.moving and opened_on_the_way.time == pytest.approx(trace.moves[5].end_time - before)
    assert trace.messages == ["Zyklus fertig"]


def test_without_a_part_it_says_so_and_goes_home():
    trace = pickcell().run({})
    assert trace.messages == ["Kein Teil am Band"] and len(trace.moves) == 2  # home, then home again after 5 s
    assert trace.moves[1].end_time > 5.0
