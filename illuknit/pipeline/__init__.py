"""The design stages as one call each: from pictures to ranked designs (and what knitting them
costs), above the floors they orchestrate (:mod:`illuknit.pipeline.stages`)."""
