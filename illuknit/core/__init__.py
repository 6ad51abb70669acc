"""Core types every floor shares: the pattern and its file, what a viewer sees, colours,
errors, the machine description, progress, lazy names and atomic file writing."""
