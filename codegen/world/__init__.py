"""The cell as solid objects: shapes, the arm's capsules, exact distances, swept moves and loads from shape."""
