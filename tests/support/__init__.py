"""Helpers the tests share: example cells, hostile names, programs to verify, simulated calibration data."""
