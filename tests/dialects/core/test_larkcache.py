"""The grammars' parser tables kept on disk (larkdoor.open_cached): loaded when fresh, rebuilt when stale or corrupt."""

from __future__ import annotations

from pathlib import Path

import pytest

import codegen
from codegen.dialects.core import larkdoor
from codegen.dialects.core.parsing import open_grammar
from codegen.dialects.dtrans import interpreter as dtrans
from codegen.dialects.urscript import interpreter as urscript

PROGRAM = "def main():\n  x = [1,\n    2]\n  textmsg(x)\nend\n"  # a line end inside brackets: the postlex's


@pytest.fixture
def cache(tmp_path, monkeypatch) -> Path:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    return tmp_path / "codegen" / "lark"


def _urscript():
    return open_grammar(urscript.__file__, propagate_positions=False, postlex=urscript.BRACKETS)


def _kept(folder: Path) -> dict[str, Path]:
    return {p.name.split("-")[0]: p for p in folder.glob("*.lark")}  # one file a grammar here


def test_the_tables_are_kept_in_the_users_cache_and_parse_as_built(cache):
    built = _urscript().parse(PROGRAM)
    files = _kept(cache)
    assert set(files) == {"urscript"}
    assert Path(codegen.__file__).parent not in files["urscript"].parents
    written = files["urscript"].stat().st_mtime_ns
    loaded = _urscript()
    assert files["urscript"].stat().st_mtime_ns == written  # read, not written again
    assert loaded.parse(PROGRAM) == built


def test_a_corrupt_file_is_rebuilt(cache):
    _urscript()
    kept = _kept(cache)["urscript"]
    good = kept.read_bytes()
    kept.write_bytes(good[: len(good) // 2])  # a write cut short: the digest line holds, the tables do not
    assert _urscript().parse(PROGRAM) is not None
    assert kept.read_bytes()[:64] == good[:64] and len(kept.read_bytes()) > len(good) // 2


def test_a_stale_file_is_rebuilt(cache):
    _urscript()
    open_grammar(dtrans.__file__, propagate_positions=False)
    files = _kept(cache)
    files["urscript"].write_bytes(files["dtrans"].read_bytes())  # another grammar's tables under this one's name
    assert _urscript().parse(PROGRAM) is not None
    assert files["urscript"].read_bytes() != files["dtrans"].read_bytes()


def test_a_directory_open_to_others_is_not_used(cache, tmp_path, monkeypatch):
    cache.mkdir(parents=True)
    cache.chmod(0o777)
    (tmp_path / "file").write_text("")
    monkeypatch.setattr(larkdoor.tempfile, "gettempdir", lambda: str(tmp_path / "file"))  # no folder can go there
    assert larkdoor.cache_dir() is None
    assert _urscript().parse(PROGRAM) is not None
    assert not _kept(cache)


def test_each_set_of_options_keeps_its_own_file(cache):
    _urscript()
    open_grammar(urscript.__file__, propagate_positions=True, postlex=urscript.BRACKETS)
    files = sorted(cache.glob("urscript-*.lark"))
    assert len(files) == 2
    written = [f.stat().st_mtime_ns for f in files]
    _urscript()
    open_grammar(urscript.__file__, propagate_positions=True, postlex=urscript.BRACKETS)
    assert [f.stat().st_mtime_ns for f in files] == written  # each read, neither written over by the other
