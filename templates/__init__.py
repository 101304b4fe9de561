"""Jinja templates, one folder per controller (installed as codegen.templates)."""
