"""illuknit: computational illusion knitting.

The pipeline, one module per stage::

    image(s) -> design_single / design_double / design_headon / solve_design (ranked designs)
             (quantise_image -> compile_single_view / assign_tiles / solve / optimise)
             -> LogicalPattern -> can_see, render -> lower_to_stitches -> schedule -> write_knitout
             -> check_knitout

The public API is re-exported here and imported lazily, so ``import illuknit`` stays fast.
"""

from __future__ import annotations

from illuknit.lazy import lazy_api

__version__ = "0.1.0"

# public name -> module that defines it
_API: dict[str, str] = {
    # model
    "LogicalPattern": "illuknit.pattern",
    "Yarn": "illuknit.pattern",
    "parse_yarns": "illuknit.pattern",
    "save_pattern": "illuknit.pattern",
    "load_pattern": "illuknit.pattern",
    # boolean views
    "can_see": "illuknit.views",
    "view_a": "illuknit.views",
    "view_b": "illuknit.views",
    "view_headon": "illuknit.views",
    "logical_error": "illuknit.views",
    # image input
    "load_image": "illuknit.images",
    "resize_to_units": "illuknit.images",
    "quantise_image": "illuknit.images",
    "QuantisedImage": "illuknit.images",
    # code-drawn inputs (benchmarks, demos)
    "draw_text": "illuknit.drawings",
    "draw_shape": "illuknit.drawings",
    "skimage_image": "illuknit.drawings",
    # single-view compiler
    "compile_single_view": "illuknit.single_view",
    # previews, charts
    "write_previews": "illuknit.previews",
    "written_instructions": "illuknit.chart",
    # design stages: pictures -> ranked designs (docs/library.md)
    "design_single": "illuknit.design.stages",
    "design_double": "illuknit.design.stages",
    "design_headon": "illuknit.design.stages",
    "design_tiles": "illuknit.design.stages",
    "solve_design": "illuknit.design.stages",
    "illusion_model": "illuknit.design.stages",
    "quantise_targets": "illuknit.design.stages",
    "RankedDesign": "illuknit.design.stages",
    "SingleDesign": "illuknit.design.stages",
    "TileDesign": "illuknit.design.stages",
    "SolvedDesign": "illuknit.design.stages",
    "SearchOptions": "illuknit.design.options",
    "RankOptions": "illuknit.design.options",
    "SolveOptions": "illuknit.design.options",
    "RankBy": "illuknit.design.options",
    "Brightness": "illuknit.design.options",
    "PictureEdits": "illuknit.design.options",
    "ModelKind": "illuknit.design.options",
    "WarmStart": "illuknit.design.options",
    # knitting (knitout for V-bed machines)
    "knit_pattern": "illuknit.knit.pipeline",
    "KnitResult": "illuknit.knit.pipeline",
    "KnitOptions": "illuknit.knit.options",
    "Catching": "illuknit.knit.options",
    "PathPlanning": "illuknit.knit.options",
    "MachineSpec": "illuknit.knit.machine",
    "resolve_machine": "illuknit.knit.machine",
    "schedule_mixed": "illuknit.knit.mixed",
    # knitout checker
    "check_knitout": "illuknit.check",
    "CheckReport": "illuknit.check",
    "Finding": "illuknit.check",
    # tiles: double-view and head-on design (docs/tiles.md)
    "Tile": "illuknit.tiles.tile",
    "TileBank": "illuknit.tiles.bank",
    "canonical_bank": "illuknit.tiles.bank",
    "load_bank": "illuknit.tiles.bank",
    "TileAssignment": "illuknit.tiles.assignment",
    "assign_tiles": "illuknit.tiles.assign",
    "compile_tiles": "illuknit.tiles.compile",
    "assign_headon": "illuknit.tiles.headon",
    # renderer, gradient design, calibration (docs/render.md)
    "RenderParams": "illuknit.render.params",
    "load_params": "illuknit.render.params",
    "render_views": "illuknit.render.raycast",
    "render_pattern": "illuknit.render.raycast",
    "render_at": "illuknit.render.raycast",
    "optimise_design": "illuknit.render.optimise",
    "calibration_swatch": "illuknit.render.calibrate",
    "fit_bump_height": "illuknit.render.calibrate",
    # constraint models and solvers (docs/solvers.md)
    "Model": "illuknit.model",
    "KnitWeights": "illuknit.illusion_models",
    "IllusionProblem": "illuknit.illusion_models",
    "build_model": "illuknit.illusion_models",
    "solve_illusion": "illuknit.illusion_models",
    "pattern_from_solution": "illuknit.illusion_models",
    "report_pattern": "illuknit.illusion_models",
    # errors
    "IlluknitError": "illuknit.errors",
}

__all__ = ["__version__", *_API]


__getattr__, __dir__ = lazy_api(__name__, _API)
