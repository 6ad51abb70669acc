"""The design stages as one call each: from pictures to ranked designs (and what knitting them
costs), above the floors they orchestrate. One module per kind of stage: :mod:`.single`,
:mod:`.tiles` (searched and ranked in :mod:`.tile_search`), :mod:`.solve`, :mod:`.measure` and
:mod:`.legible`; what they return in :mod:`.designs`, the checks and the
:class:`~illuknit.pipeline.inputs.PictureOptions` they share in :mod:`.inputs`;
:mod:`illuknit.pipeline.stages` gathers their public names."""
