"""tri layer (see README for the architecture)."""
