"""[cell.io]: the work pose's output, the feedback it waits for, and each signal as the controller names it."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cache

from codegen.controllers import get_target, target_names
from codegen.model.loader import Loader, build
from codegen.model.schema import Key, Table

SIGNAL_PATTERN = r"[A-Za-z][A-Za-z0-9_]{0,31}"  # a configured I/O signal's name (RAPID: EIO)
NAMED = "a signal name (a letter, then letters, digits or _; 32 at most)"
# a target of the cell whose programs cannot set or read a signal must not get a program without it
NO_SIGNALS = (
    "{target} programs have no digital I/O instructions (targets/{target}.toml): take {target} out of cell.targets or "
    "the signal out of the cell"
)
TIMEOUT_S = 2.0
POLL_S = 0.05  # how often a program looks at the feedback while it waits (as the vision handshake)
# A number on a group of digital inputs (a PLC's part queue): 16 bits wide, x and z in 0.1 mm offset by 32768 so
# that a negative x fits (raw = round(10 x) + 32768); an encoder's live count as a group of its own
GROUP_BITS = 16
OFFSET = 32768
SCALE = 10.0  # counts per mm of x and z on a group


def signal_key(target: str, doc: str) -> Key:
    """A digital signal as one controller names it (targets/<t>.toml signals): a number in its range or a name."""
    facts = get_target(target).program["signals"]
    if facts["form"] == "index":
        low, high = facts["range"]
        return Key(
            "integer", doc, low=low, high=high, controllers=target, expected=f"a {target} signal number {low}..{high}"
        )
    return Key("string", doc, pattern=SIGNAL_PATTERN, controllers=target, expected=NAMED)


def signal_targets() -> tuple[str, ...]:
    """The controllers whose programs set and read digital signals."""
    return tuple(t for t in target_names() if get_target(t).program.get("signals"))


def signals(doc: str, required: bool = False) -> Key:
    """A signal per target of the cell (its number or name there)."""
    return Key(
        "map",
        doc,
        required=required,
        names=signal_targets(),
        per_name={t: signal_key(t, f"the signal on {t}") for t in signal_targets()},
        controllers=", ".join(signal_targets()),
        per_target=True,
        lacking=NO_SIGNALS,
    )


@cache
def io_table() -> Table:
    """[cell.io]: the definition the loader reads."""
    return Table(
        "The work pose's output (a gripper, a clamp) and the feedback input that confirms it (optional).",
        {
            "output": signals("the output the program sets at the work pose, per target of the cell", required=True),
            "value": Key("boolean", "the value the output is set to", default=True),
            "feedback": signals("the input that confirms the action, per target (none: no feedback)"),
            "timeout_s": Key(
                "number",
                "how long the program waits for the feedback",
                unit="s",
                low=4 * POLL_S,
                high=600.0,
                default=TIMEOUT_S,
            ),
        },
    )


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
    """[cell.io] of a cell file (optional), read by its declaration (io_table): every target of the cell names its
    output, and its feedback when any does. Errors name the key."""
    if "io" not in cell_table:
        return None
    return build(SignalSettings, Loader(ctx, targets=tuple(targets)).table(io_table(), cell_table["io"], "cell.io"))


def signal_name(target, kind: str, value) -> str:
    """The signal as the interpreter knows it ("output" or "input"): the target's pattern with the index."""
    return target.program["signals"][kind].format(n=value)


def polls(settings: SignalSettings) -> int:
    return math.ceil(settings.timeout_s / POLL_S - 1e-9)


GRIPPER_BEHAVIOURS = ("prompt", "silent", "stuck", "late")  # silent: never confirms; stuck: never releases
LATE_SHARE = 0.8  # a late gripper confirms after this share of the program's timeout
