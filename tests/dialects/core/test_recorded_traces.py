"""The example cells' programs run as the interpreter ran them when the traces were recorded, bit for bit."""

from __future__ import annotations

import json

import pytest

from tests.dialects.core.record_traces import RECORDED
from tests.dialects.core.tracedigest import digest, example_runs, run_text

pytestmark = pytest.mark.slow


def test_every_recorded_trace_is_run_again_bit_for_bit():
    recorded = json.loads(RECORDED.read_text())
    seen, differ = set(), []
    for key, program, setup, arm, limit in example_runs():
        seen.add(key)
        if recorded.get(key) != digest(run_text(program, setup, arm, limit)):
            differ.append(key)
    assert seen == set(recorded), "the example runs are not the recorded ones (record again: record_traces.py)"
    assert not differ, f"{len(differ)} of {len(seen)} traces differ from the recording, first: {differ[:5]}"
