"""Palletizing (source 004) as a program kind: the [[pallet]] tables, a stacking program per pallet and target."""

from __future__ import annotations

from codegen.protocol import Kind

KIND = Kind(
    "pallet",
    order=20,
    target_keys={
        "files": list,  # a program's files per [[pallet]] ("...{pallet}..."); with `task`, the task's modules too
        "node_files": list,  # a second program per [[pallet]]: the same program in another form (a Script node's)
        "task": bool,  # every pallet's program in one task: its files once, "{pallet}" files once per pallet
        "shared_flags": bool,  # a program can write the other pallets' holds flags (its grip clears them)
        "counters": dict,  # layer and box: the counters' names for --input and verify; holds: the grip flag's
        "kept": dict,  # layer and box: where the program reports the counters, if not in counters
        "store": str,  # where the counters outlive a reload and a regeneration: a file, "plc", "program"
        "store_attribute": str,  # the module attribute the store's file carries (a program load leaves its module)
        "kept_data": list,  # the data types a program load must not reset (taught frames): declared in the store alone
        "declares": list,  # the words that begin a declaration in the language (after others: LOCAL, GLOBAL)
        "registers": int,  # the first register of the counters, where the controller keeps them in the PLC
        "registers_max": int,  # the last register the counters may use
        "written": str,  # the "counters written" toggle ("{layer}": the layer's number): the PLC copies at its change
        "level_only": bool,  # no pose product: a level pallet only
        "joint_blend": bool,  # a joint move may blend into the next (false: it stops at its point)
        "input_stops": bool,  # reading an input stops the advance run: the move before a check ends exactly
        "asks": bool,  # the program can ask the operator Yes/No (after a stop during a release: is the item down?)
        "asks_within_s": float,  # the operator's time to answer before the program stops (absent: it waits)
    },
    planner="codegen.kinds.pallet.plan:plan",
    section="codegen.kinds.pallet.analysis:SectionPart",
    writer="codegen.kinds.pallet.writer:WriterPart",
    derivation="codegen.kinds.pallet.derivation:DerivationPart",
    verify="codegen.kinds.pallet.verify:VerifyPart",
    scene="codegen.kinds.pallet.scenepart:ScenePart",
    commands="codegen.kinds.pallet.commands:CommandsPart",
)
