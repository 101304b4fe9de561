"""The interpreter's verified case against the hand-written one, per target, in CPU seconds, the two interleaved.

bench_verify.py's one-core loop (the demo cases with the edge-case station, the program loaded once) and the same
cases by benchmarks/handwritten.py, timed with time.process_time and run in turns (interpreter, hand-written,
interpreter, ...), so that a shared machine's load falls on both alike. Prints, per target, the median cases/s of
each and their ratio (the range of the ratio over the pairs in brackets).

Run: python benchmarks/interp_ratio.py [--targets ur,kuka,abb,dtrans] [--repeat N]
"""

from __future__ import annotations

import argparse
import statistics
import time

import bench_verify
import handwritten


def measure(target: str, repeat: int) -> tuple[list[float], list[float], int]:
    """cases/s of the interpreter's verified case and of the hand-written one, repeat pairs."""
    bench_verify._load(target)
    state = bench_verify._STATE
    cases = state["cases"]
    bench_verify._verify_slice((target, 0, 50))  # warm: each station's code compiled on its first run
    interpreted, hand = [], []
    for _ in range(repeat):
        start = time.process_time()
        count, mismatches = bench_verify._verify_slice((target, 0, 1))
        interpreted.append(count / (time.process_time() - start))
        assert mismatches == 0, f"{target}: {mismatches} mismatches"
        start = time.process_time()
        problems = sum(handwritten.case(state["cell"], target, one) is not None for one in cases)
        hand.append(len(cases) / (time.process_time() - start))
        assert problems == 0, f"{target}: the hand-written case disagrees with the reference {problems} times"
    return interpreted, hand, len(cases)


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--targets", default="ur,kuka,abb,dtrans")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    for target in args.targets.split(","):
        one, hand, count = measure(target, args.repeat)
        pairs = [a / b for a, b in zip(one, hand, strict=True)]
        print(
            f"{target:7} interpreter {statistics.median(one):7.0f} ({min(one):.0f}-{max(one):.0f})  "
            f"hand-written {statistics.median(hand):7.0f} ({min(hand):.0f}-{max(hand):.0f})  "
            f"ratio {statistics.median(one) / statistics.median(hand):.2f} ({min(pairs):.2f}-{max(pairs):.2f})  "
            f"{count} cases",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
