"""illuknit: computational illusion knitting.

The pipeline, one module per stage::

    image(s) -> design_single / design_double / design_headon / solve_design (ranked designs)
             (quantise_image -> compile_single_view / assign_tiles / solve / optimise)
             -> LogicalPattern -> can_see, render -> lower_to_stitches -> schedule -> write_knitout
             -> check_knitout

The public API is re-exported here and imported lazily, so ``import illuknit`` stays fast.
"""

from __future__ import annotations

import os

# registers how the IRs' read-only mappings pickle (before any IR is made)
import illuknit.core.frozen  # noqa: F401
from illuknit.core.lazy import lazy_api
from illuknit.core.source_tree import find_top_level_folders

#: The one place the version is written (pyproject reads it: ``[tool.setuptools.dynamic]``).
__version__ = "0.1.0"

find_top_level_folders(os.path.dirname(__file__))

# public name -> module that defines it
_API: dict[str, str] = {
    # model
    "LogicalPattern": "illuknit.core.pattern",
    "Yarn": "illuknit.core.pattern",
    "parse_yarns": "illuknit.core.pattern",
    "save_pattern": "illuknit.core.pattern",
    "load_pattern": "illuknit.core.pattern",
    # boolean views
    "can_see": "illuknit.core.views",
    "view_a": "illuknit.core.views",
    "view_b": "illuknit.core.views",
    "view_headon": "illuknit.core.views",
    "logical_error": "illuknit.core.views",
    # image input
    "load_image": "illuknit.pictures.images",
    "resize_to_units": "illuknit.pictures.images",
    "quantise_image": "illuknit.pictures.images",
    "QuantisedImage": "illuknit.pictures.images",
    # code-drawn inputs (benchmarks, demos)
    "draw_text": "illuknit.pictures.drawings",
    "draw_shape": "illuknit.pictures.drawings",
    "skimage_image": "illuknit.pictures.drawings",
    # single-view compiler
    "compile_single_view": "illuknit.design.single_view",
    # previews, charts
    "write_previews": "illuknit.outputs.previews",
    "written_instructions": "illuknit.outputs.chart",
    # design stages: pictures -> ranked designs (docs/library.md)
    "design_single": "illuknit.pipeline.single",
    "design_double": "illuknit.pipeline.tiles",
    "design_headon": "illuknit.pipeline.tiles",
    "design_tiles": "illuknit.pipeline.tiles",
    "solve_design": "illuknit.pipeline.solve",
    "illusion_model": "illuknit.pipeline.solve",
    "quantise_targets": "illuknit.pipeline.solve",
    "measure_design": "illuknit.pipeline.measure",
    "retile_design": "illuknit.pipeline.measure",
    "RankedDesign": "illuknit.pipeline.designs",
    "SingleDesign": "illuknit.pipeline.designs",
    "TileDesign": "illuknit.pipeline.designs",
    "SolvedDesign": "illuknit.pipeline.designs",
    "PictureOptions": "illuknit.pipeline.inputs",
    "SearchOptions": "illuknit.design.options",
    "RankOptions": "illuknit.design.options",
    "SolveOptions": "illuknit.design.options",
    "RankBy": "illuknit.design.options",
    "RankChoice": "illuknit.design.rank_choice",
    "Brightness": "illuknit.design.options",
    "PictureEdits": "illuknit.design.options",
    "ModelKind": "illuknit.design.options",
    "WarmStart": "illuknit.design.options",
    # knitting (knitout for V-bed machines)
    "knit_pattern": "illuknit.knitting.pipeline",
    "KnitResult": "illuknit.knitting.pipeline",
    "KnitOptions": "illuknit.knit.options",
    "Catching": "illuknit.knit.options",
    "PathPlanning": "illuknit.knit.options",
    "MachineSpec": "illuknit.core.machine",
    "resolve_machine": "illuknit.core.machine",
    "schedule_mixed": "illuknit.knit.mixed",
    # knitout checker
    "check_knitout": "illuknit.check",
    "CheckReport": "illuknit.check",
    "Finding": "illuknit.check",
    # tiles: double-view and head-on design (docs/tiles.md)
    "Tile": "illuknit.design.tiles.tile",
    "TileBank": "illuknit.design.tiles.bank",
    "canonical_bank": "illuknit.design.tiles.bank",
    "load_bank": "illuknit.design.tiles.bank",
    "TileAssignment": "illuknit.design.tiles.assignment",
    "assign_tiles": "illuknit.design.tiles.assign",
    "AssignOptions": "illuknit.design.tiles.assign",
    "compile_tiles": "illuknit.design.tiles.compile",
    "assign_headon": "illuknit.design.tiles.headon",
    # renderer, gradient design, calibration (docs/render.md)
    "RenderParams": "illuknit.design.render.params",
    "load_params": "illuknit.design.render.params",
    "render_views": "illuknit.design.render.raycast",
    "render_pattern": "illuknit.design.render.raycast",
    "render_at": "illuknit.design.render.raycast",
    "optimise_design": "illuknit.design.render.optimise",
    "GradientOptions": "illuknit.design.render.gradient_options",
    "calibration_swatch": "illuknit.design.render.calibrate",
    "fit_bump_height": "illuknit.design.render.calibrate",
    # constraint models and solvers (docs/solvers.md)
    "Model": "illuknit.solvers.model",
    "KnitWeights": "illuknit.design.models.illusion_models",
    "IllusionProblem": "illuknit.design.models.illusion_models",
    "build_model": "illuknit.design.models.illusion_models",
    "solve_illusion": "illuknit.design.models.illusion_models",
    "pattern_from_solution": "illuknit.design.models.illusion_models",
    "report_pattern": "illuknit.design.models.illusion_models",
    # errors
    "IlluknitError": "illuknit.core.errors",
}

__all__ = ["__version__", *_API]


__getattr__, __dir__ = lazy_api(__name__, _API)
