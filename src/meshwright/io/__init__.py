"""io layer (see README for the architecture)."""
