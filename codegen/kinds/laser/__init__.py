"""Source 003's automatic tool calibration with two laser displacement sensors."""
