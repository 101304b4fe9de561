"""Verify's cache: keys from content, entries trusted only when whole and their own."""

from __future__ import annotations

import json
from pathlib import Path

from codegen.plant import cache as cache_module
from codegen.plant.cache import FORMAT, Cache, cache_folder, verify_key

OPTIONS = {"targets": [], "cases": 5, "seed": 0, "step_limit": None}


def test_the_key_changes_with_each_input_and_only_then():
    key = verify_key(b"[cell]\n", [("a.mod", b"x")], OPTIONS)
    assert key == verify_key(b"[cell]\n", [("a.mod", b"x")], dict(OPTIONS))
    assert key != verify_key(b"[cell] \n", [("a.mod", b"x")], OPTIONS)  # the cell file's bytes
    assert key != verify_key(b"[cell]\n", [("a.mod", b"y")], OPTIONS)  # a program file's bytes
    assert key != verify_key(b"[cell]\n", [], OPTIONS)
    for option, value in (("cases", 6), ("seed", 1), ("step_limit", 10), ("targets", ["ur"])):
        assert key != verify_key(b"[cell]\n", [("a.mod", b"x")], {**OPTIONS, option: value})


def test_the_key_changes_with_codegen_itself(monkeypatch):
    key = verify_key(b"[cell]\n", [], OPTIONS)
    monkeypatch.setattr(cache_module, "codegen_digest", lambda: "another codegen")
    assert verify_key(b"[cell]\n", [], OPTIONS) != key
    monkeypatch.setattr(cache_module, "version", lambda: "9.9.9")
    assert verify_key(b"[cell]\n", [], OPTIONS) != key


def test_codegen_digest_covers_code_templates_and_targets():
    files = {p.name for root in ("codegen", "templates", "targets") for p in _digested(root)}
    assert {"engine.py", "grammar.lark", "catalogue.toml", "ur.toml", "derived.json"} <= files
    assert not any(name.endswith(".pyc") for name in files)


def _digested(label: str):
    from codegen import data_dir

    package = Path(cache_module.codegen.__file__).resolve().parent
    root = package if label == "codegen" else data_dir(label)
    return list(cache_module._files(root, skip=package / "examples"))


def test_an_entry_round_trips_and_leaves_no_temporary_file(tmp_path: Path):
    store = Cache(tmp_path)
    key = "ab" + "0" * 62
    assert store.get(key) is None and not store.unreadable  # a miss is no unreadable entry
    assert store.put(key, {"rows": [1]}) is None
    assert store.get(key) == {"rows": [1]}
    assert [p.name for p in store.path(key).parent.iterdir()] == [f"{key}.json"]


def test_a_truncated_foreign_or_other_format_entry_is_not_trusted(tmp_path: Path):
    store = Cache(tmp_path)
    key, other = "ab" + "0" * 62, "ab" + "1" * 62
    store.put(key, {"rows": [1]})
    whole = store.path(key).read_text()
    cases = {
        "truncated": whole[: len(whole) // 2],
        "not json": "\x00\x01",
        "foreign key": whole.replace(key, other),
        "other format": json.dumps({"format": 0, "key": key, "result": {"rows": [1]}}),
        "no result": json.dumps({"format": FORMAT, "key": key}),
        "a list": "[]",
    }
    for name, text in cases.items():
        store.path(key).write_text(text)
        store.unreadable.clear()
        assert store.get(key) is None, name
        assert store.unreadable == {key}, name


def test_an_unwritable_folder_costs_the_cache_not_the_run(tmp_path: Path):
    (tmp_path / "file").write_text("")
    problem = Cache(tmp_path / "file").put("ab" + "0" * 62, {})
    assert problem is not None and "cannot write the cache entry" in problem


def test_the_cache_folder_option_then_environment_then_plant_then_default(tmp_path: Path, monkeypatch):
    monkeypatch.delenv("CODEGEN_CACHE_DIR", raising=False)
    assert cache_folder(None, None, tmp_path) == tmp_path / ".codegen-cache"
    assert cache_folder(None, tmp_path / "p", tmp_path) == tmp_path / "p"
    monkeypatch.setenv("CODEGEN_CACHE_DIR", str(tmp_path / "env"))
    assert cache_folder(None, tmp_path / "p", tmp_path) == tmp_path / "env"
    assert cache_folder(str(tmp_path / "given"), tmp_path / "p", tmp_path) == tmp_path / "given"
