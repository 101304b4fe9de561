"""Many cells at once: a plant's cells found, verified through one executor, cached and reported."""
