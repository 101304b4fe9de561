"""Each KindTests subclass runs for every target that has its kind's programs in the example cells."""

from kind_base import targets_of


def pytest_generate_tests(metafunc):
    kind = getattr(metafunc.cls, "kind", None)
    if kind is not None and "pair" in metafunc.fixturenames:
        pairs = targets_of(kind)
        metafunc.parametrize("pair", pairs, ids=[target for target, _ in pairs])
