"""The counters' store after a reload of a pallet program: kept where the target keeps them, declared nowhere else."""

from __future__ import annotations

import re

from codegen.kinds.pallet.kind import KIND


def reload_proof(target) -> bool:
    """The counters outlive a reload of the program: kept in a file of their own or in the PLC (targets/<t>.toml
    [program.pallet] store), not in the program's own variables."""
    return KIND.facts(target).get("store", "program") != "program"


def declared_outside_store(source, target, names: tuple[str, str]) -> str | None:
    """After a reload the counters hold what their store kept: a counter declared in another of the program's files
    (one a regeneration replaces, its value with it) fails."""
    store = KIND.facts(target).get("store", "")
    words = KIND.facts(target).get("declares")
    if not words or "." not in store:
        return None
    # a line whose first words are a declaration's (LOCAL PERS num, DECL GLOBAL INT) and that names the counter
    pattern = rf"^[ \t]*(?:\w+[ \t]+)*?(?:{'|'.join(map(re.escape, words))})\b[^\n]*\b{{name}}\b"
    store_suffix = store[store.index(".") :].lower()
    for f in source.files:
        name = f.name.rsplit("/", 1)[-1].lower()
        if name.endswith(store_suffix) and (name.startswith("pallet_data") or name.endswith("_count" + store_suffix)):
            continue
        for counter in names:
            if re.search(pattern.format(name=re.escape(counter)), f.text, re.M | re.I):
                return (
                    f"{counter} is declared in {name}, which a regeneration replaces: a reload sets it back "
                    f"(the counters belong in {store.replace('{pallet}', '<pallet>')} alone)"
                )
    return None


def taught_outside_store(source, target) -> str | None:
    """The taught data (targets/<t>.toml [program.pallet] kept_data: RAPID's tooldata and wobjdata) are declared in
    the store alone: declared in a program module, a program load sets a TCP or pallet frame measured at
    commissioning back to its generated value."""
    types, words, store = (KIND.facts(target).get(k) for k in ("kept_data", "declares", "store"))
    if not types or not words or not store:
        return None
    declare, typed = "|".join(map(re.escape, words)), "|".join(map(re.escape, types))
    pattern = rf"^[ \t]*(?:\w+[ \t]+)*?(?:{declare})[ \t]+({typed})[ \t]+(\w+)"
    for f in source.files:
        name = f.name.rsplit("/", 1)[-1]
        if name.lower() == store.lower():
            continue
        found = re.search(pattern, f.text, re.M | re.I)
        if found:
            return (
                f"{found.group(1)} {found.group(2)} is declared in {name}, which a program load replaces: a TCP or "
                f"frame taught there goes back to its generated value (taught data belong in {store})"
            )
    return None


def store_not_kept(source, target) -> str | None:
    """The store's module carries the attribute that keeps it through a program load (targets/<t>.toml
    [program.pallet] store_attribute: RAPID's SYSMODULE, a system module): without it a load of the program replaces
    the store, and the counters with it."""
    attribute, store = KIND.facts(target).get("store_attribute"), KIND.facts(target).get("store", "")
    if attribute is None:
        return None
    for f in source.files:
        if f.name.rsplit("/", 1)[-1].lower() != store.lower():
            continue
        header = re.search(r"^[ \t]*MODULE[ \t]+\w+[ \t]*(?:\(([^)]*)\))?", f.text, re.M | re.I)
        given = {a.strip().upper() for a in (header.group(1) or "").split(",")} if header else set()
        if attribute.upper() not in given:
            return (
                f"{store} is not a {attribute} module: loading the program replaces it, and the counters with it "
                f"(the store must be a {attribute} module, loaded once)"
            )
        return None
    return f"{store}, the counters' store, is not among the program's files"
