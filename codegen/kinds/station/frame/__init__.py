"""The frame mode's other modules: its cell-file keys, the hand-eye calibration and its command, its page objects."""
