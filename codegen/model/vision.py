"""The vision PC handshake: the cell's [cell.vision] settings and the protocol every station program follows."""

from __future__ import annotations

import math
from dataclasses import dataclass

from codegen.model.loader import Loader, build
from codegen.model.schema import Key, Table

# The protocol, the same on every controller. The program writes the command, then request = ack + 1;
# the vision PC does what the command asks, writes its answer and then ack = request. The program uses
# an answer only when ack equals its own request: a reading from an earlier cycle (a vision PC that
# failed to update, or answered another request) never passes, it ends in the timeout's halt.
READ = 1  # read the station: its id (barcode) and, for a point-mode station, the mark
PHOTO = 2  # photograph the mark from where the arm stands (frame mode): pixels u, v and image angle
POLL_S = 0.05  # how often a program looks at the acknowledgement while it waits
# [cell.vision]: the definition the loader reads; a timeout of at least four polls, at most ten minutes
TABLE = Table(
    "The vision PC handshake (optional).",
    {
        "timeout_s": Key(
            "number",
            "how long a program waits for the vision PC's answer before it halts with a message",
            unit="s",
            low=4 * POLL_S,
            high=600.0,
            default=5.0,
        ),
        # the vision PC's address where a controller reaches it over a network channel (the target's [program]
        # channel: its configuration file names it); a dotted IPv4 address, each part 0..255
        "ip": Key(
            "string",
            "the vision PC's IPv4 address, where a controller's program opens a network channel to it",
            default="192.168.1.20",
            pattern=r"((25[0-5]|2[0-4][0-9]|1[0-9][0-9]|[1-9]?[0-9])\.){3}(25[0-5]|2[0-4][0-9]|1[0-9][0-9]|[1-9]?[0-9])",
            expected="an IPv4 address such as 192.168.1.20",
        ),
        "port": Key(
            "integer",
            "the vision PC's TCP port of that channel",
            low=1,
            high=65534,  # the narrowest port range of a channel's controller (targets' [program] channel)
            default=54600,
        ),
    },
)
TIMEOUT_S = TABLE.default("timeout_s")


@dataclass(frozen=True)
class VisionSettings:
    """[cell.vision]: how long a program waits for an answer before it halts with a message; where a network
    channel reaches the vision PC (its address and port)."""

    timeout_s: float = TIMEOUT_S
    ip: str = TABLE.default("ip")
    port: int = TABLE.default("port")


def parse_settings(ctx, cell_table: dict) -> VisionSettings:
    """[cell.vision] of a cell file (optional), read by its declaration (TABLE); errors name the key."""
    if "vision" not in cell_table:
        return VisionSettings()
    return build(VisionSettings, Loader(ctx).table(TABLE, cell_table["vision"], "cell.vision"))


def polls(settings: VisionSettings) -> int:
    """The number of POLL_S waits a program makes before it gives up (the timeout, rounded up)."""
    return math.ceil(settings.timeout_s / POLL_S - 1e-9)


# How a simulated vision PC answers (verify's cases): on time, late, never, not at all but with the
# last cycle's reading still in its registers, twice, with another sequence number, or promptly after
# a late answer to the previous cycle's last request (which that cycle gave up on) arrives first.
PREVIOUS_REQUEST = 41  # the previous cycle's last answered request
# Over a network channel also: the connection lost as the request arrives (dropped), an answer without one of its
# values (incomplete); over variables both answer nothing (codegen.sim.vision_pc).
BEHAVIOURS = (
    "prompt", "late", "too_late", "never", "stale", "twice", "other_sequence", "late_previous", "dropped", "incomplete",
)  # fmt: skip
UNANSWERED = frozenset(
    {"too_late", "never", "stale", "other_sequence", "dropped", "incomplete"}
)  # a correct program halts
SECOND_LOOK_MM = 0.5  # "twice": the second answer reads the mark this much further along x and y
PROMPT_S = 0.02  # a prompt answer's latency (less than one poll: most runs wait once)


def latency(settings: VisionSettings, behaviour: str) -> float:
    """How long the simulated vision PC takes: prompt; late, within the timeout; too late, after it."""
    return {"late": 0.8 * settings.timeout_s, "too_late": settings.timeout_s + 1.0}.get(behaviour, PROMPT_S)


def answered(target, behaviour: str) -> dict:
    """The handshake's variables at the start, by the program's names: the previous cycle's request
    answered, or (late_previous) one request more that it gave up on."""
    names = target.program.get("photo")
    if names is None:
        return {}
    unanswered = PREVIOUS_REQUEST + 1 if behaviour == "late_previous" else PREVIOUS_REQUEST
    acked = {names["ack"]: PREVIOUS_REQUEST} if "ack" in names else {}  # over a channel the answer carries it
    return {names["request"]: unanswered, **acked}


def lost(target, behaviour: str) -> bool:
    """Whether the program can tell that the vision PC went off the network: over a channel that models the
    connection (the target's [program] channel), not over variables (nothing answers: the timeout's stop)."""
    return behaviour == "dropped" and target.program.get("channel") is not None
