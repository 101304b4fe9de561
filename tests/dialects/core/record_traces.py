"""Record the example programs' traces into recorded/traces.json: python -m tests.dialects.core.record_traces.

The recording pins the interpreter's runs of the example programs: test_recorded_traces.py holds every later
interpreter to it, bit for bit, so a faster interpreter cannot change a run unnoticed. Record again only where a run
is meant to change (a program, a case or the controller's semantics changed), and say why in the commit."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from tests.dialects.core.tracedigest import digest, example_runs, run_text

RECORDED = Path(__file__).parent / "recorded" / "traces.json"


def main() -> int:
    out = {}
    for key, program, setup, arm, limit in example_runs():
        if key in out:
            raise SystemExit(f"two runs named {key}")
        out[key] = digest(run_text(program, setup, arm, limit))
    RECORDED.write_text(json.dumps(out, indent=0, sort_keys=True) + "\n")
    print(f"{len(out)} runs recorded in {RECORDED}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
