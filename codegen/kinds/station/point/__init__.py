"""The point mode's helpers: its cell-file keys, its float64 reference, `codegen correct`, its page objects."""
