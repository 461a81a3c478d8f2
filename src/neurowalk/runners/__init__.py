"""Running many episodes: a local process pool (default)."""
