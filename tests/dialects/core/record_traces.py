"""Record the example programs' traces (tests/dialects/core/recorded/traces.json): python -m tests.dialects.core.record_traces."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from tests.dialects.core.tracedigest import digest, example_runs, run_text

RECORDED = Path(__file__).parent / "recorded" / "traces.json"


def main() -> int:
    out = {}
    for key, program, setup, arm, limit in example_runs():
        out[key] = digest(run_text(program, setup, arm, limit))
    RECORDED.write_text(json.dumps(out, indent=0, sort_keys=True) + "\n")
    print(f"{len(out)} runs recorded in {RECORDED}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
