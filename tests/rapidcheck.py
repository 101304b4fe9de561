"""Run the independent RAPID checker rapidchecker on a module, minus its one known grammar gap."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

# rapidchecker (PyPI) has no LOCAL routines: it rejects `LOCAL PROC`, which the RAPID manual allows
# ("Technical reference manual - RAPID kernel", routine declarations: LOCAL makes a routine local to
# its module), while it accepts LOCAL data. The check reads the module with that word removed from
# routine declarations; test_rapidchecker_lacks_local_routines shows the gap still exists.
LOCAL_ROUTINE = re.compile(r"^(\s*)LOCAL (PROC|FUNC|TRAP) ", re.MULTILINE)


def rapidchecker(text: str, path: Path) -> subprocess.CompletedProcess:
    path.write_text(LOCAL_ROUTINE.sub(r"\1\2 ", text), encoding="utf-8")
    return subprocess.run([sys.executable, "-m", "rapidchecker", str(path)], capture_output=True, text=True)


def rapidchecker_raw(text: str, path: Path) -> subprocess.CompletedProcess:
    path.write_text(text, encoding="utf-8")
    return subprocess.run([sys.executable, "-m", "rapidchecker", str(path)], capture_output=True, text=True)
