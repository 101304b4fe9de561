"""The cell in 3D: a self-contained page of the arm, the cell's objects and the interpreter's traces."""
