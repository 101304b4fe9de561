"""A program kind from outside codegen's tree (the tests'): one package with its templates and an example cell."""
