"""geometry layer (see README for the architecture)."""
