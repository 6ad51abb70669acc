"""Design: from pictures to ranked illusion patterns (single view, tiles, constraint models)."""
