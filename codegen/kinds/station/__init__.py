"""The station kind: the cell's [[station]] tables and their one program; point, frame, ... are its modes (modes/)."""
