"""sizing layer (see README for the architecture)."""
