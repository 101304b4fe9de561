"""The kinds' derivations driven: their identities proven, their closed forms printed per dialect (sympy: here and in
the kinds' derivation modules), cached in derived.json."""

from __future__ import annotations

import json
import random
import sys
from dataclasses import dataclass

import sympy as sp

from codegen.derived import CACHE_PATH
from codegen.dialects import printers
from codegen.protocol import installed_kinds

# --- identities ------------------------------------------------------------------------------


@dataclass(frozen=True)
class Identity:
    name: str
    statement: str
    expected: str  # "holds" or "refuted"
    status: str  # "holds", "refuted" or "unproven"
    detail: str

    @property
    def as_expected(self) -> bool:
        return self.status == self.expected


def _conventions(key: str) -> list:
    """Every kind's derivation.symbols()[key], in the registry's order."""
    return [v for kind in installed_kinds().values() for v in kind.derivation.symbols().get(key, ())]


def _simplify_zero(expr) -> bool:
    expr = sp.Matrix(expr) if isinstance(expr, sp.MatrixBase) else sp.Matrix([expr])
    return all(sp.simplify(sp.expand_trig(sp.expand(e))) == 0 for e in expr)


def _counterexample(expr, fixed: dict | None = None, seed: int = 7) -> str | None:
    """A rational point where expr is visibly non-zero (|value| > 1e-6), or None."""
    rng = random.Random(seed)
    expr = sp.Matrix(expr) if isinstance(expr, sp.MatrixBase) else sp.Matrix([expr])
    free = sorted(set().union(*(e.free_symbols for e in expr)) | set(_conventions("free")), key=str)
    small = _conventions("small")
    for _ in range(20):
        point = {s: sp.Rational(rng.randint(-900, 900), 10) for s in free}
        point.update({s: sp.Rational(rng.randint(-300, 300), 1000) for s in small})
        if fixed:
            point.update(fixed)
        values = [sp.N(e.subs(point)) for e in expr]
        worst = max(abs(v) for v in values)
        if worst > 1e-6:
            shown = ", ".join(f"{k}={point[k]}" for k in free if expr.has(k))
            return f"at {shown}: residual {sp.N(worst, 6)}"
    return None


def _check(name: str, statement: str, expected: str, residual, fixed: dict | None = None) -> Identity:
    if _simplify_zero(residual):
        return Identity(name, statement, expected, "holds", "residual simplifies to 0")
    witness = _counterexample(residual, fixed)
    if witness is not None:
        return Identity(name, statement, expected, "refuted", witness)
    return Identity(name, statement, expected, "unproven", "not simplified to 0, no counterexample")


def derive() -> dict:
    """Each kind's derivation (sympy), by kind name: what its description and identities read."""
    return {name: kind.derivation.derive() for name, kind in installed_kinds().items()}


def identities(derivations: dict | None = None) -> list[Identity]:
    """Every kind's identities, in the registry's order, each proven on its kind's derivation (derivations: derive()'s
    result where the caller has it; a kind computes its own once per process either way)."""
    del derivations
    return [identity for kind in installed_kinds().values() for identity in kind.derivation.identities(_check)]


# --- export for the printers -----------------------------------------------------------------


def cse_blocks() -> dict[str, dict]:
    """Every kind's printed blocks with common subexpressions eliminated, the kinds' readable names given."""
    exprs, groups = {}, []
    readable = {}
    derivations = [kind.derivation for kind in installed_kinds().values()]
    for derivation in derivations:
        readable.update(derivation.symbols().get("readable", {}))
    for derivation in derivations:  # each kind's own closed forms the controllers evaluate
        for block, outputs in derivation.printed_blocks().items():
            exprs.update(outputs)
            groups.append((block, tuple(outputs)))
    blocks = {}
    for block, names in groups:
        temps, reduced = sp.cse(
            [exprs[n] for n in names], symbols=sp.numbered_symbols(f"{block}_t"), optimizations="basic"
        )
        renames = {tmp: sp.Symbol(readable[expr], real=True) for tmp, expr in temps if expr in readable}
        temps = [(renames.get(tmp, tmp), expr.subs(renames)) for tmp, expr in temps]
        reduced = [expr.subs(renames) for expr in reduced]
        blocks[block] = {"temps": temps, "outputs": dict(zip(names, reduced, strict=True))}
    return blocks


def describe(derivations: dict | None = None) -> str:
    """Every kind's derivation as `codegen derive` prints it."""
    d = derive() if derivations is None else derivations
    texts = [kind.derivation.describe(d[name]) for name, kind in installed_kinds().items()]
    return "\n\n".join(text for text in texts if text)


# --- cache (read by codegen.derived without sympy) -------------------------------------------


def build_cache() -> dict:
    """Everything later steps need from the derivation, as plain JSON data."""

    d = derive()
    blocks = cse_blocks()
    printed = {}
    for dialect, printer in printers().items():
        printed[dialect] = {
            name: {
                "temps": [[str(tmp), printer.doprint(expr)] for tmp, expr in block["temps"]],
                "outputs": {out: printer.doprint(expr) for out, expr in block["outputs"].items()},
            }
            for name, block in blocks.items()
        }
    return {
        "description": describe(d),
        "identities": [
            {"name": i.name, "statement": i.statement, "expected": i.expected, "status": i.status, "detail": i.detail}
            for i in identities(d)
        ],
        "blocks": {
            name: {
                "temps": [[str(tmp), sp.sstr(expr)] for tmp, expr in block["temps"]],
                "outputs": {out: sp.sstr(expr) for out, expr in block["outputs"].items()},
            }
            for name, block in blocks.items()
        },
        "printed": printed,
    }


if __name__ == "__main__":
    text = json.dumps(build_cache(), indent=1, sort_keys=True) + "\n"
    if "--write" in sys.argv:
        CACHE_PATH.write_text(text, encoding="utf-8")
        print(f"wrote {CACHE_PATH}")
    else:
        sys.stdout.write(text)
