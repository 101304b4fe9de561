"""Point correction (source 000): one camera reading moves every taught pose of the station rigidly."""
