"""Design: pictures -> logical patterns (single view, tiles, constraint models, gradient)."""
