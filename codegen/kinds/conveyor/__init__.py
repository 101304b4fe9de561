"""Conveyor tracking (source 002): the [conveyor] section and its calibration from touched points."""
