"""Each KindTests subclass runs for every target that has its kind's programs in the example cells (a model
mutation: for each of them whose cell has what it changes; a text mutation: for each of them written for the target)."""

import pytest
from kind_base import model_mutations_of, targets_of, text_mutations_of
from support.cells import unstacking_clear_q_text

from codegen.model.cell import load_cell

# (kind, target, model mutation) run with the slow tests only: each is the same common check (the tool's payload, the
# work speed, the start's tolerance: verify's checks every kind gets) on a target whose other kinds' programs the
# default run mutates alike, and the same kind's catch of it on the kind's other targets; they are the kinds' longest
# mutation runs (7.5 s of CPU the three, measured in one process)
SLOW_MODEL_MUTATIONS = {
    ("laser", "ur", "payload_x10"),  # default: station, pallet, conveyor on ur; laser on kuka and abb
    ("laser", "ur", "start_tolerance_30deg"),  # the same
    ("laser", "ur", "work_speed_x1_7"),  # the same
}


def pytest_generate_tests(metafunc):
    kind = getattr(metafunc.cls, "kind", None)
    if kind is None or "pair" not in metafunc.fixturenames:
        return
    if "model_mutation" in metafunc.fixturenames:
        both = [
            pytest.param(pair, mutation, id=f"{pair[0]}-{mutation}", marks=_slow((kind, pair[0], mutation)))
            for pair, mutation in model_mutations_of(kind)
        ]
        metafunc.parametrize(("pair", "model_mutation"), both)
    elif "text_mutation" in metafunc.fixturenames:
        both = text_mutations_of(kind)
        ids = [f"{target}-{mutation}" for (target, _), mutation in both]
        metafunc.parametrize(("pair", "text_mutation"), both, ids=ids)
    else:
        pairs = targets_of(kind)
        metafunc.parametrize("pair", pairs, ids=[target for target, _ in pairs])


def _slow(key: tuple[str, str, str]) -> list:
    return [pytest.mark.slow] if key in SLOW_MODEL_MUTATIONS else []


@pytest.fixture(scope="session")
def unstacking(tmp_path_factory):
    """Source 004's test cell unstacking, its Q moved clear: one Cell per process, so its reach and clearance proofs
    are worked out once for every test that reads it (tests/conftest.py's GROUPS keeps those tests on one worker)."""
    path = tmp_path_factory.mktemp("unstacking") / "testmat_pallet.toml"
    path.write_text(unstacking_clear_q_text(), encoding="utf-8")
    return load_cell(path)
