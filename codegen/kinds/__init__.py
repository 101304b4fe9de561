"""The program kinds, one package each with its kind.py; codegen.protocol discovers them (nothing names them)."""
