"""Verify's results stored by content: a key hashing everything a result depends on, entries written atomically
and trusted only when they name their own key."""

from __future__ import annotations

import hashlib
import json
import os
import platform
import tempfile
from functools import cache
from pathlib import Path

import numpy as np

import codegen
from codegen import data_dir

FORMAT = 2  # the entries' layout; another number is another cache
CACHE_ENV = "CODEGEN_CACHE_DIR"
DEFAULT_FOLDER = ".codegen-cache"
SOURCE_SUFFIXES = frozenset({".py", ".lark", ".json", ".toml", ".j2", ".js", ".css", ".html"})


@cache
def codegen_digest() -> str:
    """sha256 over codegen's own files (its code, grammars, catalogue, derivation cache, templates and the targets'
    facts), by relative path: a changed codegen never meets an entry of another one. The bundled examples are
    cells, not code, and are left out."""
    package = Path(codegen.__file__).resolve().parent
    digest = hashlib.sha256()
    for label, root in (("codegen", package), ("templates", data_dir("templates")), ("targets", data_dir("targets"))):
        for path in sorted(_files(root, skip=package / "examples")):
            digest.update(f"{label}/{path.relative_to(root).as_posix()}\0".encode())
            digest.update(hashlib.sha256(path.read_bytes()).digest())
    return digest.hexdigest()


def _files(root: Path, skip: Path):
    for path in root.rglob("*"):
        if (
            path.suffix in SOURCE_SUFFIXES
            and path.is_file()
            and skip not in path.parents
            and "__pycache__" not in path.parts
        ):
            yield path


def version() -> str:
    from importlib.metadata import PackageNotFoundError
    from importlib.metadata import version as package_version

    try:
        return package_version("codegen")
    except PackageNotFoundError:
        return "unknown"


def verify_key(cell_bytes: bytes, program_files: list[tuple[str, bytes]], options: dict) -> str:
    """The key of one cell's verify result: the cell file's bytes, the program files verified (name and bytes; none
    when they are rendered fresh from the cell and codegen), codegen's version and the digest of its files (code,
    templates, the targets' facts), the Python and numpy that compute, and the options that change the result
    (targets, cases, seed, step limit)."""
    parts = {
        "format": FORMAT,
        "what": "verify",
        "codegen": version(),
        "codegen_files": codegen_digest(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "cell": hashlib.sha256(cell_bytes).hexdigest(),
        "programs": [[name, hashlib.sha256(data).hexdigest()] for name, data in program_files],
        "options": options,
    }
    return hashlib.sha256(json.dumps(parts, sort_keys=True).encode()).hexdigest()


def cache_folder(given: str | Path | None, plant_default: Path | None, root: Path) -> Path:
    """--cache-dir, else $CODEGEN_CACHE_DIR, else the plant's `cache`, else .codegen-cache/ in the plant's folder."""
    if given is not None:
        return Path(given)
    if os.environ.get(CACHE_ENV, "").strip():
        return Path(os.environ[CACHE_ENV])
    return plant_default if plant_default is not None else root / DEFAULT_FOLDER


class Cache:
    """Entries under FOLDER/verify/<key[:2]>/<key>.json. A read that fails for any reason (missing, truncated,
    not JSON, another format, another key inside) is a miss: the caller verifies again and the entry is
    rewritten. `unreadable` names the entries found but not trusted."""

    def __init__(self, folder: Path):
        self.folder = Path(folder)
        self.unreadable: set[str] = set()

    def path(self, key: str) -> Path:
        return self.folder / "verify" / key[:2] / f"{key}.json"

    def get(self, key: str) -> dict | None:
        path = self.path(key)
        try:
            raw = path.read_bytes()
        except OSError:
            return None
        try:
            entry = json.loads(raw)
            if entry["format"] == FORMAT and entry["key"] == key and isinstance(entry["result"], dict):
                return entry["result"]
        except (ValueError, KeyError, TypeError):
            pass
        self.unreadable.add(key)
        return None

    def put(self, key: str, result: dict) -> str | None:
        """Store a result (a temporary file renamed over the entry: a reader sees the old entry or the new one,
        never half of one). A folder that cannot be written costs the cache, not the run: the reason is returned."""
        path = self.path(key)
        text = json.dumps({"format": FORMAT, "key": key, "result": result}, sort_keys=True)
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            fd, temp = tempfile.mkstemp(prefix=f".{key[:12]}.", suffix=".tmp", dir=path.parent)
            try:
                with os.fdopen(fd, "w", encoding="utf-8") as f:
                    f.write(text)
                os.replace(temp, path)
            except BaseException:
                Path(temp).unlink(missing_ok=True)
                raise
        except OSError as exc:
            return f"{path}: cannot write the cache entry ({exc.strerror or exc})"
        return None
