"""The three.js bundle the package ships: built from the pinned npm packages, holding every name the viewer uses."""

from __future__ import annotations

import json
import re

from codegen.view.page import STATIC, VIEWER

JS = STATIC.parent / "js"


def _exports() -> set[str]:
    text = (JS / "entry.js").read_text(encoding="utf-8")
    return {name for block in re.findall(r"export\s*\{([^}]*)\}", text) for name in re.findall(r"\w+", block)}


def test_the_bundle_exports_every_name_the_viewer_uses():
    used = {n for name in VIEWER for n in re.findall(r"\bTHREE\.(\w+)", (STATIC / name).read_text(encoding="utf-8"))}
    bundle = (STATIC / "three.min.js").read_text(encoding="utf-8")
    assert used and used <= _exports(), sorted(used - _exports())
    assert [n for n in sorted(_exports()) if f"{n}:()=>" not in bundle] == []  # the global THREE's getters


def test_the_bundle_is_of_the_pinned_versions():
    """package.json pins exact versions, package-lock.json their archives' hashes (`npm ci` installs exactly those),
    and the bundle's banner names the three.js it holds."""
    package = json.loads((JS / "package.json").read_text(encoding="utf-8"))
    lock = json.loads((JS / "package-lock.json").read_text(encoding="utf-8"))["packages"]
    for name, version in package["devDependencies"].items():
        assert re.fullmatch(r"\d+\.\d+\.\d+", version), f"{name}: {version} is not one version"
        assert lock[f"node_modules/{name}"]["version"] == version and lock[f"node_modules/{name}"]["integrity"]
    three = package["devDependencies"]["three"]
    banner = (STATIC / "three.min.js").read_text(encoding="utf-8").split("\n", 1)[0]
    assert f"npm three@{three}," in banner and f"r{three.split('.')[1]} " in banner
