"""A run's trace as canonical text, every number by its bits: what the recorded traces of the examples hold."""

from __future__ import annotations

import hashlib

import numpy as np

from codegen.verify.runner import _run

EXAMPLES = (
    "agv_machine_tending.toml",
    "thermometer_bench.toml",
    "conveyor/belt_pick.toml",
    "laser/laser_tcp.toml",
    "pallets/eur_pallet.toml",
    "pallets/testmat_pallet.toml",
)
CASES, SEED = 3, 7  # each kind's cases per program: its edge cases and scenarios come with them


def _bits(value) -> str:
    """A value's text with every float by its bits (float.hex; numpy arrays by dtype and bytes)."""
    if value is None or isinstance(value, bool | int | str):
        return repr(value)
    if isinstance(value, float):
        return float(value).hex()
    if isinstance(value, np.ndarray):
        return f"{value.dtype}{value.shape}:{value.tobytes().hex()}"
    if isinstance(value, np.generic):
        return f"{type(value).__name__}:{value.tobytes().hex()}"
    if isinstance(value, dict):
        items = sorted(value.items(), key=lambda kv: str(kv[0]))
        return "{" + ",".join(f"{_bits(k)}:{_bits(v)}" for k, v in items) + "}"
    if isinstance(value, list | tuple):
        return "[" + ",".join(_bits(v) for v in value) + "]"
    return f"{type(value).__name__}:{value!r}"


def trace_text(trace) -> str:
    """Everything a trace records, one line per part, numbers bit for bit."""
    lines = [f"halted {trace.halted} {trace.halt_message!r} steps {trace.steps} clock {_bits(trace.clock)}"]
    lines.append(f"ended {trace.ended!r} simulated {trace.simulated!r} warnings {trace.warnings!r}")
    lines += [f"message {_bits(t)} {m!r}" for m, t in zip(trace.messages, trace.message_times, strict=True)]
    for move in trace.moves:
        lines.append(
            f"move {move.kind} {move.file}:{move.line} {_bits(move.tcp2base)} joints {_bits(move.joints)} "
            f"sols {_bits(move.solutions)} t {_bits(move.start_time)}-{_bits(move.end_time)} "
            f"settings {_bits(move.settings)} arc {move.arc is not None}"
        )
    for out in trace.outputs:
        lines.append(
            f"output {out.name} {out.value} {out.line} {_bits(out.time)} {out.moving} {out.after_moves} "
            f"{_bits(out.tcp2base)}"
        )
    lines.append(f"kept {_bits(trace.kept)}")
    return "\n".join(lines)


def run_text(program, setup, arm, step_limit: int) -> str:
    """The case's run as text: its trace, or the error it ends in (with the trace until then)."""
    try:
        return trace_text(_run(program, setup, arm, step_limit))
    except Exception as exc:  # an error is a recorded outcome like a trace
        trace = getattr(exc, "trace", None)
        return f"error {type(exc).__name__}: {exc}\n" + (trace_text(trace) if trace is not None else "")


def digest(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()


def example_runs():
    """(key, program, setup, arm) for each example cell's programs (every kind, every target) and their cases."""
    from codegen.dialects.core.machine import DEFAULT_STEP_LIMIT
    from codegen.model.cell import DEMO_CELL, load_cell
    from codegen.verify.checks import Checker
    from codegen.verify.engine import _fresh

    examples = DEMO_CELL.parent
    for name in EXAMPLES:
        cell = load_cell(examples / name)
        for position, source in enumerate(_fresh(cell, list(cell.targets))):  # a kind's variant models share rows
            model = source.model or cell
            kind = cell.kinds[source.kind].verify
            program = source.load()
            arm = Checker(model, source.target).arm
            for number, case in enumerate(kind.cases(model, source, CASES, SEED)):
                key = f"{name} {position} {source.target} {source.ident} {number}"
                setup = kind.setup(model, source, case)
                yield key, program, setup, arm, DEFAULT_STEP_LIMIT
