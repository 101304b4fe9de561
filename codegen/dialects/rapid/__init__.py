"""RAPID (ABB): printer, grammar and interpreter."""
