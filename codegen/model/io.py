"""[cell.io]: the work pose's output, the feedback it waits for, and each signal as the controller names it."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

from codegen.controllers import get_target

SIGNAL_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,31}")  # a configured I/O signal's name (RAPID: EIO)
TIMEOUT_S = 2.0
POLL_S = 0.05  # how often a program looks at the feedback while it waits (as the vision handshake)


@dataclass(frozen=True)
class SignalSettings:
    """[cell.io]: at the work pose the program sets `output` to `value` (a gripper closing, a clamp), then
    waits until the `feedback` input is on (the sensor that confirms the action; if the cell names one)
    for at most timeout_s; per target, the signal as the controller names it (an index or a configured
    name, targets/<t>.toml signals)."""

    output: dict  # target -> index or name
    value: bool = True
    feedback: dict = field(default_factory=dict)  # target -> index or name; empty: no feedback
    timeout_s: float = TIMEOUT_S


def parse_settings(ctx, cell_table: dict, targets) -> SignalSettings | None:
    """[cell.io] of a cell file (optional); every target of the cell names its output, and its feedback
    when any does. Errors name the key."""
    if "io" not in cell_table:
        return None
    table = ctx.table(cell_table, "io", "cell.io")
    ctx.no_unknown(table, {"output", "value", "feedback", "timeout_s"}, "cell.io")
    output = per_target(ctx, table, "output", targets, required=True)
    feedback = per_target(ctx, table, "feedback", targets, required=False)
    value = table.get("value", True)
    if not isinstance(value, bool):
        ctx.fail("cell.io.value", f"must be true or false, got {value!r}")
    timeout = ctx.number(table, "timeout_s", "cell.io.timeout_s") if "timeout_s" in table else TIMEOUT_S
    if not 4 * POLL_S <= timeout <= 600:
        ctx.fail("cell.io.timeout_s", f"must be between {4 * POLL_S:g} and 600 s, got {timeout}")
    return SignalSettings(output, value, feedback, timeout)


def per_target(ctx, table: dict, key: str, targets, required: bool, prefix: str = "cell.io") -> dict:
    """A signal per target of the cell (table[key][target]), checked against the target's signal facts."""

    if key not in table:
        if required:
            ctx.fail(f"{prefix}.{key}", "required: the signal per target of the cell (its number or name there)")
        return {}
    raw = ctx.table(table, key, f"{prefix}.{key}")
    out = {}
    for target in targets:
        path = f"{prefix}.{key}.{target}"
        facts = get_target(target).program.get("signals")
        if facts is None:  # a program that cannot set the signal must not be made without it
            ctx.fail(
                prefix,
                f"{target} programs have no digital I/O instructions (targets/{target}.toml): "
                f"take {target} out of cell.targets or the signal out of the cell",
            )
        if target not in raw:
            ctx.fail(path, "missing: every target of the cell names the signal")
        value = raw[target]
        if facts["form"] == "index":
            low, high = facts["range"]
            if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
                ctx.fail(path, f"expected a {target} signal number {low}..{high}, got {value!r}")
        elif not isinstance(value, str) or not SIGNAL_NAME.fullmatch(value):
            ctx.fail(path, f"expected a signal name (a letter, then letters, digits or _; 32 at most), got {value!r}")
        out[target] = value
    ctx.no_unknown(raw, set(targets), f"{prefix}.{key}")
    return out


def signal_name(target, kind: str, value) -> str:
    """The signal as the interpreter knows it ("output" or "input"): the target's pattern with the index."""
    return target.program["signals"][kind].format(n=value)


def polls(settings: SignalSettings) -> int:
    return math.ceil(settings.timeout_s / POLL_S - 1e-9)


GRIPPER_BEHAVIOURS = ("prompt", "silent", "stuck", "late")  # silent: never confirms; stuck: never releases
LATE_SHARE = 0.8  # a late gripper confirms after this share of the program's timeout
