"""KRL values read before anything sets them: a data list's variables, a routine's own variables, the frames a motion
needs (findings of `codegen check`)."""

from __future__ import annotations

from lark import Token, Tree

from codegen.dialects.core.files import Finding
from codegen.dialects.core.kept import STORE
from codegen.dialects.core.parsing import node_start
from codegen.dialects.krl.modules import routine_name


def _root_var(node):
    """The variable an assignment target or argument stands on (N, N.X, N[2], N[]), None if none."""
    while isinstance(node, Tree) and node.data != "var":
        if not node.children:
            return None
        node = node.children[0]
    return str(node.children[0]).upper() if isinstance(node, Tree) else None


def _set_names(node) -> set:
    """The variables a tree may set: assignment targets, FOR counters, arguments (an OUT parameter's)."""
    out = set()
    for sub in node.iter_subtrees():
        if sub.data == "assign":
            out.add(_root_var(sub.children[0]))
        elif sub.data == "for_stmt":
            out.add(str(sub.children[0]).upper())
        elif sub.data == "args":
            out.update(_root_var(a) for a in sub.children if isinstance(a, Tree))
    return out


def _unset_read(file: str, token, where: str) -> Finding:
    return Finding(
        file,
        token.line,
        token.column,
        "warning",
        "unset-variable",
        f"{token} is read but nothing in {where} sets it: KSS stops here (variable value invalid)",
    )


def unset_data(trees) -> list[Finding]:
    """A data list's variable declared without a value that no module of the program sets, read by a routine
    (one without a variable of its own of that name)."""
    unset = {}
    for _file, tree in trees:
        for defdat in (n for n in tree.children if isinstance(n, Tree) and n.data == "defdat"):
            for item in defdat.iter_subtrees_topdown():
                if item.data == "decl_item" and item.children[1] is None and item.children[2] is None:
                    unset.setdefault(str(item.children[0]).upper(), item.children[0])
    for file, tree in trees:
        for key in STORE.by_unit(_set_names_of, file, tree):
            unset.pop(key, None)
    out = []
    for file, tree in trees:
        for key, token in STORE.by_unit(_outer_reads, file, tree):
            if key in unset:
                out.append(_unset_read(file, token, "the program's files"))
                del unset[key]  # one finding a variable
    return out


def _set_names_of(_file: str, tree) -> list:
    return list(_set_names(tree))


def _outer_reads(_file: str, tree) -> list[tuple[str, Token]]:
    """The variables each routine reads that are not its own (no DECL or parameter of that name), in order."""
    out = []
    for routine in (n for n in tree.children if isinstance(n, Tree) and n.data in ("def_routine", "def_function")):
        own = {str(i.children[0]).upper() for i in routine.iter_subtrees() if i.data in ("decl_item", "param")}
        for sub in routine.iter_subtrees_topdown():
            key = str(sub.children[0]).upper() if sub.data == "var" else None
            if key is not None and key not in own:
                out.append((key, sub.children[0]))
    return out


def unset_locals(name: str, tree) -> list[Finding]:
    """A routine's own variable (DECL in a .src has no value) read but set nowhere in the routine: not by an
    assignment, a FOR, or as an argument (a routine or built-in may set it through an OUT parameter). KSS stops
    where it is read ("variable value invalid"); run finds it only when the read runs."""
    out = []
    for routine in (n for n in tree.children if isinstance(n, Tree) and n.data in ("def_routine", "def_function")):
        body = routine.children[-1]
        params = {str(p.children[0]).upper() for p in routine.iter_subtrees() if p.data == "param"}
        local = {}
        for decl in (c for c in body.children if isinstance(c, Tree) and c.data == "decl"):
            for item in (c for c in decl.children if isinstance(c, Tree) and c.data == "decl_item"):
                key = str(item.children[0]).upper()
                if item.children[1] is None and item.children[2] is None and key not in params:
                    local[key] = item.children[0]
        if not local:
            continue
        set_names = _set_names(body)
        reported = set()
        for sub in body.iter_subtrees_topdown():
            if sub.data != "var":
                continue
            key = str(sub.children[0]).upper()
            if key in local and key not in set_names and key not in reported:
                reported.add(key)
                out.append(_unset_read(name, sub.children[0], routine_name(routine)))
        out.extend(_reads_before_set(name, routine, {k: v for k, v in local.items() if k in set_names}))
    return out


_LOOPS = ("while_stmt", "for_stmt", "loop_stmt", "repeat_stmt")


def _setters(body, names: set[str]) -> tuple[dict[str, list], set[int]]:
    """The statements that may set each of the names (an assignment to it or a part of it, a FOR on it, a call
    passing it), and the var nodes that are such a setting itself (an assignment's target, an argument)."""
    setters: dict[str, list] = {}
    setting: set[int] = set()
    for sub in body.iter_subtrees():
        if sub.data == "assign":
            targets = [sub.children[0]]
        elif sub.data == "for_stmt":
            key = str(sub.children[0]).upper()
            if key in names:
                setters.setdefault(key, []).append(sub)
            continue
        elif sub.data in ("call_stmt", "call") and isinstance(sub.children[1], Tree):
            targets = [a for a in sub.children[1].children if isinstance(a, Tree)]
        else:
            continue
        for target in targets:
            root = target
            while isinstance(root, Tree) and root.data != "var" and root.children:
                root = root.children[0]
            key = str(root.children[0]).upper() if isinstance(root, Tree) and root.data == "var" else None
            if key in names:
                setters.setdefault(key, []).append(sub)
                setting.add(id(root))
    return setters, setting


def _reads_before_set(file: str, routine, local: dict) -> list[Finding]:
    """A routine's own variable read before the first statement that may set it (in a routine without GOTO, the
    read and every setting not in one loop: the read cannot come after a setting): KSS stops at the read
    ("variable value invalid"); run finds it only when the read runs."""
    body = routine.children[-1]
    if not local or any(True for _ in body.find_data("goto_stmt")):
        return []
    setters, setting = _setters(body, set(local))
    loops = [(node_start(n)[0], _last_line(n)) for n in body.iter_subtrees() if n.data in _LOOPS]
    out, reported = [], set()
    for statement in body.iter_subtrees_topdown():
        if statement.data != "var" or id(statement) in setting:
            continue
        key, token = str(statement.children[0]).upper(), statement.children[0]
        if key not in setters or key in reported:
            continue
        at = (token.line, token.column)
        earlier = [s for s in setters[key] if node_start(s) < at and not _inside(token, s)]
        together = any(
            low <= token.line <= high and any(low <= node_start(s)[0] <= high for s in setters[key])
            for low, high in loops
        )
        if not earlier and not together:
            reported.add(key)
            message = f"{token} is read before anything in {routine_name(routine)} sets it: KSS stops here "
            message += "(variable value invalid)"
            out.append(Finding(file, token.line, token.column, "warning", "unset-variable", message))
    return out


def _last_line(node) -> int:
    """The line of a statement's last token (its end, as far as the tree keeps it)."""
    return max((t.line for t in node.scan_values(lambda v: isinstance(v, Token)) if t.line), default=0)


def _inside(token, node) -> bool:
    """Whether a token is part of a statement."""
    return node_start(node) <= (token.line, token.column) and token.line <= _last_line(node)


FRAME_SETTERS = {"#INITMOV", "#TOOL", "#BASE", "#FRAMES", "#PTP_PARAMS", "#CP_PARAMS"}


def unset_frames(trees) -> list[Finding]:
    """The program's first motion before $TOOL and $BASE are set (by an assignment, BAS(#INITMOV), BAS(#TOOL /
    #BASE / #PTP_PARAMS / #CP_PARAMS / #FRAMES) or the motion's WITH): it moves with the tool and base the
    previous program left. Followed through the main routine and the routines it calls, in program order."""
    name, tree = trees[0]
    routines = {
        routine_name(n): (file, n)
        for file, t in trees
        for n in t.children
        if isinstance(n, Tree) and n.data in ("def_routine", "def_function")
    }
    main = next((n for n in tree.children if isinstance(n, Tree) and n.data == "def_routine"), None)
    if main is None:
        return []
    state = {"tool": False, "base": False, "seen": set(), "moved": False}
    return _walk(main, name, routines, state)


def _walk(node, file: str, routines: dict, state: dict) -> list[Finding]:
    for sub in node.iter_subtrees_topdown():
        if sub.data == "assign" or sub.data == "with_item":
            root = sub.children[0]
            while isinstance(root, Tree) and root.data != "var":
                root = root.children[0]
            target = str(root.children[0]).upper() if isinstance(root, Tree) else ""
            state["tool"] |= target == "$TOOL"
            state["base"] |= target == "$BASE"
        elif sub.data in ("call_stmt", "call"):
            called = str(sub.children[0]).upper()
            args = sub.children[1].children if sub.children[1] is not None else []
            if called == "BAS" and args and isinstance(args[0], Tree) and args[0].data == "enum":
                command = "#" + str(args[0].children[0]).upper()
                if command in FRAME_SETTERS:
                    state["tool"] |= command != "#BASE"
                    state["base"] |= command != "#TOOL"
            elif called in routines and called not in state["seen"]:
                state["seen"].add(called)
                found = _walk(routines[called][1], routines[called][0], routines, state)
                if state["moved"]:
                    return found
        elif sub.data in ("motion_stmt", "circ_stmt"):
            with_clause = next((c for c in sub.children if isinstance(c, Tree) and c.data == "with_clause"), None)
            if with_clause is not None:
                _walk(with_clause, file, routines, state)
            state["moved"] = True
            if not (state["tool"] and state["base"]):
                missing = " and ".join(n for n, ok in (("$TOOL", state["tool"]), ("$BASE", state["base"])) if not ok)
                line, column = node_start(sub)
                return [
                    Finding(
                        file,
                        line,
                        column,
                        "warning",
                        "motion-before-tool-base",
                        f"a motion before {missing} is set (BAS(#INITMOV, 0), the inline form's "
                        "BAS(#PTP_PARAMS ...), or an assignment): it moves with what the previous program "
                        "left",
                    )
                ]
            return []
    return []
