"""The design stages: from pictures to ranked designs, one library call per kind of illusion.

=====================  ========================================================================
stage                  what it returns
=====================  ========================================================================
:func:`design_single`  :class:`SingleDesign`: the single-view pattern for each stripe order
                       (paper section 5), ranked by how well each shows the picture
:func:`design_double`  :class:`TileDesign`: tile designs showing one picture from above and
                       another from below (paper section 6), ranked by how they read
:func:`design_headon`  :class:`TileDesign`: tile designs showing a picture head-on that
                       disappears at an angle (paper Fig. 17)
:func:`design_tiles`   the same from pictures already quantised (what the app calls)
:func:`solve_design`   :class:`SolvedDesign`: the pattern a constraint model and a solver find
                       (paper section 4), with the solver's answer and its report
:func:`measure_design` how one pattern reads (a design edited by hand), as the ranking measures
:func:`retile_design`  a tile design compiled again with per-pair tile overrides
=====================  ========================================================================

Every stage takes frozen option objects (:mod:`illuknit.design.options`), returns a frozen
result whose designs carry their measures and their rank key (why each ranks where it does),
and never changes its inputs. Knitting a design is the next step,
:func:`~illuknit.knitting.pipeline.knit_pattern` (a machine name or spec, and
:class:`~illuknit.knit.options.KnitOptions`). The commands ``illuknit single``, ``double``,
``headon`` and ``solve``, the app and the benchmark call these stages and only write what they
return, so a script calling them reproduces the commands' files (``docs/library.md``).

The stages live one module per kind: :mod:`~illuknit.pipeline.single`,
:mod:`~illuknit.pipeline.tiles` (searched and ranked in :mod:`~illuknit.pipeline.tile_search`),
:mod:`~illuknit.pipeline.solve` and :mod:`~illuknit.pipeline.measure`, what they return in
:mod:`~illuknit.pipeline.designs` and the checks they share in :mod:`~illuknit.pipeline.inputs`;
this module gathers their public names (the import path the stages have always had).
"""

from __future__ import annotations

from illuknit.pipeline.designs import (
    Picture,
    Progress,
    RankedDesign,
    SingleDesign,
    SolvedDesign,
    Stripe,
    TileDesign,
)
from illuknit.pipeline.inputs import PictureOptions
from illuknit.pipeline.measure import measure_design, retile_design
from illuknit.pipeline.single import design_single
from illuknit.pipeline.solve import illusion_model, quantise_targets, solve_design
from illuknit.pipeline.tiles import design_double, design_headon, design_tiles

__all__ = [
    "Picture",
    "PictureOptions",
    "Progress",
    "RankedDesign",
    "SingleDesign",
    "SolvedDesign",
    "Stripe",
    "TileDesign",
    "design_double",
    "design_headon",
    "design_single",
    "design_tiles",
    "illusion_model",
    "measure_design",
    "quantise_targets",
    "retile_design",
    "solve_design",
]
