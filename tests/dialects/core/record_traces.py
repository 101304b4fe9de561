"""Record the example programs' traces into recorded/traces.json: python -m tests.dialects.core.record_traces.

The recording is of the interpreter as it was before its speed work (commit 03da570, run from an export of that
commit's tree): test_recorded_traces.py holds every later interpreter to it, bit for bit. Record again only where a
run is meant to change, and say why in the commit."""

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
