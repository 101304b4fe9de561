"""The point mode's other modules: its cell-file keys, its float64 reference, `codegen correct`, its page objects."""
