"""Every program kind on the one base (tests/kinds/kind_base.py): its programs, its scenarios, the mutation harness."""

from kind_base import KindTests


class TestStation(KindTests):
    kind = "station"


class TestPallet(KindTests):
    kind = "pallet"


class TestConveyor(KindTests):
    kind = "conveyor"


class TestLaser(KindTests):
    kind = "laser"
