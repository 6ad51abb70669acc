"""Design: pictures -> logical patterns (single view, tiles, constraint models, gradient)."""

# design's own algorithms (the DP, the descent, the gradient) register as solver backends
import illuknit.design.models.backends  # noqa: F401
