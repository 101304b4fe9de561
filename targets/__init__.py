"""Controller facts, one TOML file per controller (installed as codegen.targets)."""
