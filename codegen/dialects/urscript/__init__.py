"""URScript (Universal Robots): printer, grammar and interpreter."""
