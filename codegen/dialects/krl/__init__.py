"""KRL (KUKA Robot Language, KSS 8): printer, grammar and interpreter."""
