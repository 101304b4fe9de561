"""codegen: vision-corrected robot programs, derived with sympy and verified by interpretation."""

__version__ = "0.1.0"


def data_dir(name: str):
    """templates/ or targets/: installed inside the package as codegen.<name>; in a source checkout
    whose codegen/ is imported directly (python -m pytest at the top), the folder beside it."""
    from importlib.resources import files
    from pathlib import Path

    try:
        return Path(str(files(f"codegen.{name}")))
    except ModuleNotFoundError:
        return Path(__file__).resolve().parent.parent / name
