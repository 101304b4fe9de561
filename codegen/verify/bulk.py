"""The bulk runs of an integer input over its range, one run per class of the program's checks of it plus a sample."""

from __future__ import annotations

import itertools
import math
import random
import re
import zlib
from collections.abc import Iterable

# Why one run stands for its class. The input (a station id) reaches the program's control flow through checks of
# the value against numbers: `station_id == 7`, `CASE 1, 2`, `weizhi > 20000`, an array's bounds. The outcome of a
# check `id OP c` (OP one of == <> < <= > >=) as a function of an integer id changes only at c (between c - 1, c and
# c + 1; for a fractional c at its floor and ceiling). Every number written in the program's files is such a c
# wherever it is (a literal of any notation below, in code, data lists or strings alike: a number taken that is not
# compared costs a few runs and no strictness), and each becomes a breakpoint with its neighbours. Between two
# breakpoints every such check gives the same answer for every id, so every id there takes the same path through
# the program: the same statements, moves and stop; what differs is the id itself, which the program only prints
# (the unknown-id message), so the class is also cut where the printed id gains a digit (powers of ten) and where a
# controller's integer could change its width (powers of two). A class's ids therefore all run as its
# representative does, and each breakpoint id is a class of its own: an extra dispatch branch (`CASE 1, 20000`)
# names its id in the program, so that id is run and fails.
# What the classes cannot see: a check against a value the program computes (`id == 19990 + 10`, an id's digit
# sum). For those a sample of ids drawn over the whole range runs too (seeded by the program's text: the same ids in
# every worker and every run of that program, other ids for another program).

SAMPLE = 256  # ids drawn at random over the whole range, beyond the classes' representatives
_NUMBER = re.compile(
    r"0[xX][0-9a-fA-F]+"  # hexadecimal, C style
    r"|'[Hh][0-9a-fA-F]+'"  # hexadecimal in quotes ('H1F')
    r"|'[Bb][01]+'"  # binary in quotes ('B101')
    r"|\d+(?:\.\d*)?(?:[eE][+-]?\d+)?"  # decimal, fraction and exponent
    r"|\.\d+(?:[eE][+-]?\d+)?"
)


def _value(token: str) -> float:
    if token[:2] in ("0x", "0X"):
        return int(token[2:], 16)
    if token.startswith("'"):
        return int(token[2:-1], 16 if token[1] in "Hh" else 2)
    return float(token)


def breakpoints(texts: Iterable[str], ids: range) -> set[int]:
    """The ids where a check of the input against a number of the program's text can change its answer: each number's
    floor and ceiling with their neighbours, the printed id's digit counts and the integer widths, the range's ends."""
    out = {ids.start, ids.stop - 1}
    for text in texts:
        for token in _NUMBER.findall(text):
            value = _value(token)
            if not math.isfinite(value) or value > ids.stop:
                continue
            low, high = math.floor(value), math.ceil(value)
            out.update((low - 1, low, high, high + 1))
    for power in range(1, len(str(ids.stop)) + 1):  # the printed id gains a digit
        out.update((10**power - 1, 10**power))
    for bits in range(1, ids.stop.bit_length() + 1):  # a controller's integer of that many bits
        out.update((2**bits - 1, 2**bits))
    return {i for i in out if ids.start <= i < ids.stop}


def representatives(texts: list[str], ids: range, sample: int = SAMPLE) -> list[int]:
    """The ids of `ids` to run: every breakpoint, one id inside each class between two (its middle), and a sample of
    the range seeded by the texts; in increasing order."""
    cuts = sorted(breakpoints(texts, ids))
    chosen = set(cuts)
    chosen.update((a + b) // 2 for a, b in itertools.pairwise(cuts) if b - a > 1)
    seed = zlib.crc32("\0".join(texts).encode("utf-8"))
    chosen.update(random.Random(seed).sample(ids, min(sample, len(ids))))
    return sorted(chosen)
