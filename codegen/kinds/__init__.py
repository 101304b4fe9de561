"""The program kinds, one package each whose kind.py makes its Kind; pyproject.toml's entry-point group
`codegen.kinds` lists them (codegen.protocol.installed_kinds)."""
