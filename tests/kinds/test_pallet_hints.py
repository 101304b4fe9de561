"""The pallet's hints: one support warning a pallet, with its layers and boxes; another family that fits more boxes;
each naming the pallet by its name, as generate's and verify's messages do."""

from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner

from codegen.cli import main
from codegen.kinds.pallet.report import load_pallet_file

EUR = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "pallets" / "eur_pallet.toml"


def test_the_support_warning_comes_once_a_pallet_with_its_layers_and_boxes():
    """It came once per pair of patterns: twice for the EUR example's alternating interlock, the same boxes."""
    result = CliRunner().invoke(main, ["pallet", str(EUR)])
    support = [line for line in result.stderr.splitlines() if "support_min" in line]
    assert support == [
        f"warning: {EUR}: pallet 'eur': boxes that rest on less than support_min 60% of their bottom on the layer "
        "below: layer 2 (interlock_mirrored on interlock): box 1 50%, box 2 50%; "
        "layer 3 (interlock on interlock_mirrored): box 1 50%, box 2 50%"
    ]


def test_a_family_that_fits_more_boxes_is_named_once_a_family(tmp_path):
    """1200 x 800 mm, boxes 400 x 300 mm: columns of boxes turned across fit 4 x 2 = 8, the interlock 6 (as counted
    by hand in test_pallet's families test); the columns themselves get no hint."""
    hints = [w for w in load_pallet_file(EUR).warnings if "fits" in w]
    assert hints == [
        f"{EUR}: pallet 'eur' patterns.interlock: family 'column' fits 8 boxes a layer, 'interlock' 6 (a hint: keep it "
        "where its layers hold together better)"
    ]
    text = EUR.read_text(encoding="utf-8")
    old = 'interlock = { family = "interlock", label_out = true }'
    columns = text.replace(old, 'interlock = { family = "column" }')
    columns = columns.replace(
        'interlock_mirrored = { family = "interlock", label_out = true, mirror = true }',
        'interlock_mirrored = { family = "column", mirror = true }',
    )
    assert columns.count('family = "column"') == 3
    (tmp_path / "columns.toml").write_text(columns, encoding="utf-8")
    assert [w for w in load_pallet_file(tmp_path / "columns.toml").warnings if "fits" in w] == []
