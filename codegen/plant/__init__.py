"""Many cells at once: a plant's discovery, one table of results and verify's content-addressed cache."""
