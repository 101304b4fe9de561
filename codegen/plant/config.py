"""A plant: a folder of cell files, or a codegen.toml listing them and setting the plant's defaults."""

from __future__ import annotations

import glob
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from codegen.model.cell import CellError, read_cell_data

PLANT_FILE = "codegen.toml"
# folders discovery never enters: hidden ones (.git, .venv, the cache), the output and virtual environments
SKIPPED_FOLDERS = frozenset({"generated", "venv", "node_modules", "__pycache__"})
CASES_MAX = 1_000_000


class PlantError(ValueError):
    """A plant that cannot be read (its codegen.toml or a listed cell missing): `file: key: message`, exit 2."""


@dataclass(frozen=True)
class Setting:
    """One key of [plant]: its type (as TOML reads it), what it means (the reference page's words)."""

    types: tuple[type, ...]
    meaning: str


# the declared schema of codegen.toml's [plant] table (docs/plant.md shows it)
SCHEMA: dict[str, Setting] = {
    "name": Setting((str,), "the plant's name, shown above its table"),
    "cells": Setting((list,), "cell files or glob patterns, relative to the plant's folder (default: discovery)"),
    "out": Setting((str,), "output folder of generate, diff and check, relative to the plant's folder"),
    "targets": Setting((list,), "only these controllers (each cell's own targets among them)"),
    "cases": Setting((int,), "verify's random readings per station"),
    "seed": Setting((int,), "verify's random seed"),
    "step_limit": Setting((int,), "verify's step limit of one run (default: each kind's own)"),
    "cache": Setting((str,), "verify's cache folder, relative to the plant's folder"),
}


@dataclass(frozen=True)
class Plant:
    """The cells of a plant (absolute paths, in order) and its defaults; None: the command's own default."""

    root: Path
    cells: tuple[Path, ...]
    config: Path | None = None
    name: str = ""
    out: Path | None = None
    targets: tuple[str, ...] = ()
    cases: int | None = None
    seed: int | None = None
    step_limit: int | None = None
    cache: Path | None = None
    skipped: tuple[str, ...] = field(default=())  # TOML files found that are no cell files

    def output(self) -> Path:
        """The output folder: its `out`, else generated/ in the plant's folder."""
        return self.out if self.out is not None else self.root / "generated"

    def label(self, cell: Path) -> str:
        """A cell's name in the table: its path from the plant's folder."""
        try:
            return cell.relative_to(self.root).as_posix()
        except ValueError:
            return str(cell)


def load_plant(path: str | Path) -> Plant:
    """The plant at `path` (a folder, with or without a codegen.toml, or the codegen.toml itself)."""
    path = Path(path)
    if path.is_dir():
        config = path / PLANT_FILE
        if not config.is_file():
            cells, skipped = discover(path.resolve())
            return Plant(path.resolve(), cells, skipped=skipped)
    else:
        config = path
    if not config.is_file():
        raise PlantError(f"{config}: no such file")
    return _from_config(config)


def discover(root: Path, out: Path | None = None) -> tuple[tuple[Path, ...], tuple[str, ...]]:
    """Every cell file under root, sorted by path: each `*.toml` whose top level has a [cell] table, in any
    folder but hidden ones, the output folder and SKIPPED_FOLDERS. A TOML file that does not parse is listed
    (it may be a cell with a typo: its row says what is wrong); other TOML files are skipped and named."""
    cells, skipped = [], []
    for path in _toml_files(root, out.resolve() if out is not None else None):
        if path.name == PLANT_FILE:
            continue
        try:
            data, _ = read_cell_data(path)
        except CellError:
            cells.append(path)
            continue
        (cells if isinstance(data.get("cell"), dict) else skipped).append(path)
    return tuple(cells), tuple(p.relative_to(root).as_posix() for p in skipped)


def _toml_files(root: Path, out: Path | None) -> list[Path]:
    found = []
    stack = [root]
    while stack:
        folder = stack.pop()
        for entry in folder.iterdir():
            if entry.is_dir() and not entry.is_symlink():
                if entry.name.startswith(".") or entry.name in SKIPPED_FOLDERS or entry.resolve() == out:
                    continue
                stack.append(entry)
            elif entry.suffix == ".toml" and entry.is_file():
                found.append(entry)
    return sorted(found, key=lambda p: p.relative_to(root).as_posix())


def _from_config(config: Path) -> Plant:
    root = config.parent.resolve()
    try:
        data = tomllib.loads(config.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError) as exc:
        raise PlantError(f"{config}: cannot read: {getattr(exc, 'strerror', None) or exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise PlantError(f"{config}: TOML syntax error: {exc}") from None
    unknown = sorted(set(data) - {"plant"})
    if unknown:
        raise PlantError(f"{config}: {unknown[0]}: unknown table or key (codegen.toml has one table, [plant])")
    table = data.get("plant")
    if not isinstance(table, dict):
        raise PlantError(f"{config}: plant: missing [plant] table")
    for key, value in table.items():
        setting = SCHEMA.get(key)
        if setting is None:
            raise PlantError(f"{config}: plant.{key}: unknown key (known: {', '.join(SCHEMA)})")
        if not isinstance(value, setting.types) or isinstance(value, bool):
            wanted = " or ".join(_type_word(t) for t in setting.types)
            raise PlantError(f"{config}: plant.{key}: expected {wanted}, got {_type_word(type(value))}")
    for key in ("name", "out", "cache"):
        if key in table and not table[key].strip():
            raise PlantError(f"{config}: plant.{key}: empty")
    for key, low in (("cases", 0), ("seed", 0), ("step_limit", 1)):
        if key in table and not low <= table[key] <= (CASES_MAX if key == "cases" else 2**63 - 1):
            raise PlantError(f"{config}: plant.{key}: {table[key]} is out of range (at least {low})")
    targets = _strings(config, table, "targets")
    if "targets" in table:
        from codegen.controllers import target_names

        for i, name in enumerate(targets):
            if name not in target_names():
                raise PlantError(
                    f"{config}: plant.targets[{i}]: {name!r} is no controller ({', '.join(target_names())})"
                )
        if not targets:
            raise PlantError(f"{config}: plant.targets: empty (leave it out for every cell's own targets)")
    out = root / table["out"] if "out" in table else None
    if "cells" in table:
        cells, skipped = _listed(config, root, _strings(config, table, "cells")), ()
    else:
        cells, skipped = discover(root, out)
    return Plant(
        root,
        cells,
        config,
        table.get("name", ""),
        out,
        tuple(targets),
        table.get("cases"),
        table.get("seed"),
        table.get("step_limit"),
        root / table["cache"] if "cache" in table else None,
        skipped,
    )


def _strings(config: Path, table: dict, key: str) -> list[str]:
    values = table.get(key, [])
    for i, value in enumerate(values):
        if not isinstance(value, str) or not value.strip():
            raise PlantError(f"{config}: plant.{key}[{i}]: expected a non-empty string, got {value!r}")
    return values


def _listed(config: Path, root: Path, patterns: list[str]) -> tuple[Path, ...]:
    """The cells a codegen.toml lists: each entry a file or a glob pattern (matching at least one file), in the
    order listed, each file once."""
    cells: dict[Path, None] = {}
    for i, pattern in enumerate(patterns):
        if Path(pattern).is_absolute() or ".." in Path(pattern).parts:
            raise PlantError(f"{config}: plant.cells[{i}]: {pattern!r} is outside the plant's folder")
        if glob.has_magic(pattern):
            found = sorted(Path(p) for p in glob.glob(str(root / pattern), recursive=True) if Path(p).is_file())
            if not found:
                raise PlantError(f"{config}: plant.cells[{i}]: {pattern!r} matches no file")
        else:
            found = [root / pattern]
            if not found[0].is_file():
                raise PlantError(f"{config}: plant.cells[{i}]: {pattern!r}: no such file")
        for path in found:
            cells.setdefault(path, None)
    if not cells:
        raise PlantError(f"{config}: plant.cells: empty")
    return tuple(cells)


def _type_word(t: type) -> str:
    return {
        str: "a string",
        list: "an array",
        int: "an integer",
        float: "a number",
        bool: "true or false",
        dict: "a table",
    }.get(t, t.__name__)
