"""plot layer (see README for the architecture)."""
