"""Small KRL programs for the tests: files by name, loaded and run as codegen run does."""

from __future__ import annotations

from codegen.dialects import get_dialect
from codegen.dialects.core.files import SourceFile

KRL = get_dialect("krl")

# A data list as KUKA's templates write it: the BAS declaration first (every teach-pendant .dat has it)
DAT_HEAD = "DEFDAT {name}\nEXT BAS (BAS_COMMAND :IN,REAL :IN )\n"
INI = "GLOBAL INTERRUPT DECL 3 WHEN $STOPMESS==TRUE DO IR_STOPM ( )\nINTERRUPT ON 3\nBAS (#INITMOV,0 )\n"


def files(**texts: str) -> list[SourceFile]:
    """SourceFiles from name=text (a name's last underscore is its suffix's dot: main_src -> main.src; a name
    starting with config_ is $config.dat)."""
    out = []
    for key, text in texts.items():
        name = "$config.dat" if key == "config_dat" else key[::-1].replace("_", ".", 1)[::-1]
        out.append(SourceFile(name, text))
    return out


def program(body: str, decls: str = "", dat: str = "", routines: str = "", name: str = "T"):
    """One module T: a main routine with these declarations and statements, its .dat with these lines."""
    src = f"DEF {name}()\n{decls}\n{body}\nEND\n{routines}"
    data = DAT_HEAD.format(name=name) + dat + "\nENDDAT\n"
    return KRL.load_files([SourceFile(f"{name.lower()}.src", src), SourceFile(f"{name.lower()}.dat", data)])


def run(body: str, decls: str = "", dat: str = "", routines: str = "", **options):
    return program(body, decls, dat, routines).run({}, **options)


def say(expr: str) -> str:
    """KRL lines that show one number or text in a message (MsgNotify)."""
    return f"MsgNotify({expr})"
