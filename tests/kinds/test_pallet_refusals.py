"""Pallet cells generate accepted and verify failed: generated so that verify passes, or refused at load with the key
and its line."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.controllers import get_target
from codegen.kinds.pallet.program import counter_names
from codegen.kinds.pallet.reload import declared_outside_store
from codegen.model.cell import CellError, load_cell
from codegen.verify.programs import fresh_sources

EXAMPLES = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "pallets"
TESTMAT = (EXAMPLES / "testmat_pallet.toml").read_text(encoding="utf-8")


def _cell(tmp_path, text: str):
    path = tmp_path / "pallet.toml"
    path.write_text(text, encoding="utf-8")
    return load_cell(path)


def test_a_long_name_keeps_its_counters_store_recognised_on_krl(tmp_path):
    """KRL names have at most 24 characters: pal_<name>_count for a long name was shortened with a hash as a whole,
    lost its _count and with it the mark of the counters' store (verify's counters_reloaded failed: "declared in
    pal_eur_a_rather_lo_815d.dat, which a regeneration replaces"). The name is shortened, the suffix kept."""
    cell = _cell(tmp_path, TESTMAT.replace('name = "testmat"', 'name = "testmat_with_a_long_name"', 1))
    target = get_target("kuka")
    (source,) = [s for s in fresh_sources(cell, ["kuka"]) if s.kind == "pallet"]
    names = [f.name.rsplit("/", 1)[-1] for f in source.files]
    store = [n for n in names if n.endswith("_count.dat")]
    assert len(store) == 1 and len(store[0].removesuffix(".dat")) <= target.identifier_max, names
    assert declared_outside_store(source, target, counter_names(cell, target, 0)) is None


@pytest.mark.parametrize(
    ("pick", "refused"),
    [
        ("[700.0, -10.0, 200.0, 0.0, 0.0, 180.0]", True),  # over the pallet, a box there within the stack's 130 mm
        ("[700.0, -10.0, 206.0, 0.0, 0.0, 180.0]", False),  # the box at Q just clears the full stack's top
        ("[600.0, 300.0, 50.0, 0.0, 0.0, 180.0]", False),  # the example's, beside the pallet
    ],
)
def test_a_pick_place_over_the_pallet_within_the_stack_is_refused(tmp_path, pick, refused):
    text = TESTMAT.replace("pick = [600.0, 300.0, 50.0, 0.0, 0.0, 180.0]", f"pick = {pick}", 1)
    if not refused:
        _cell(tmp_path, text)
        return
    with pytest.raises(CellError, match=r"line 45: pallet\[0\]\.pick: Q is over the pallet \(at x 50\.0, y 40\.0"):
        _cell(tmp_path, text)
    (tmp_path / "bad.toml").write_text(text, encoding="utf-8")
    result = CliRunner().invoke(main, ["generate", str(tmp_path / "bad.toml"), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2 and "Traceback" not in result.output and not (tmp_path / "out").exists()
