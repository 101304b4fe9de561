"""The cell model: a cell file to frozen dataclasses; no interpreter, no kind (kinds register sections)."""
