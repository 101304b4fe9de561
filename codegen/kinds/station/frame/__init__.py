"""The frame mode's helpers: its cell-file keys, the hand-eye calibration and its command, its page objects."""
