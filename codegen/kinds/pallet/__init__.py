"""Palletizing (source 004): the [[pallet]] section, its frame, patterns, checks, poses and pictures."""
