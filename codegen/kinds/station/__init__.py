"""The cell's station program, shared by the station kinds (point, frame): its base, context and verify."""
