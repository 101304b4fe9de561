"""The station modes, one module each registering a StationMode (codegen.kinds.station.mode finds them)."""
