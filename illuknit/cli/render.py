"""``illuknit render``: ray-cast previews of a pattern from both sides, head-on, and a sweep GIF."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from illuknit.cli.options import FINITE, InputFile, outdir_option

__all__ = ["MAX_FRAME_PIXELS", "MAX_SWEEP_PIXELS", "check_render_size", "render"]

#: Largest picture one view may have (pixels): 4000 x 4000.
MAX_FRAME_PIXELS = 16_000_000
#: Largest sweep: frames x pixels per frame (held as 1-byte palette frames: about 400 MB).
MAX_SWEEP_PIXELS = 400_000_000


def check_render_size(shape: tuple[int, int], *, scale: int, frames: int) -> None:
    """Refuse renders whose output is absurdly large, suggesting a ``--scale``/``--frames`` that fits.

    A view is ``rows * scale`` x ``cols * scale`` pixels; the sweep GIF holds ``2 * frames - 2``
    frames (one side to the other and back).
    """
    from illuknit.core.errors import RenderParamsError

    rows, cols = shape
    per_frame = rows * scale * cols * scale
    gif_frames = 2 * frames - 2
    size = f"{rows * scale} x {cols * scale} pixels"
    fit_scale = max(1, int((MAX_FRAME_PIXELS / (rows * cols)) ** 0.5))
    if per_frame > MAX_FRAME_PIXELS:
        raise RenderParamsError(
            f"a view of this {rows} x {cols} pattern at --scale {scale} is {size} "
            f"(limit {MAX_FRAME_PIXELS / 1e6:.0f} megapixels); try --scale {fit_scale}"
        )
    if per_frame * gif_frames > MAX_SWEEP_PIXELS:
        fit_frames = max(2, MAX_SWEEP_PIXELS // per_frame // 2 + 1)
        sweep_scale = max(1, int((MAX_SWEEP_PIXELS / gif_frames / (rows * cols)) ** 0.5))
        raise RenderParamsError(
            f"the sweep of {gif_frames} frames of {size} is "
            f"{per_frame * gif_frames / 1e6:.0f} megapixels (limit {MAX_SWEEP_PIXELS / 1e6:.0f}); "
            f"try --frames {fit_frames} or --scale {sweep_scale}"
        )


@click.command("render")
@click.argument("pattern_file", metavar="PATTERN", type=InputFile("pattern"))
@click.option(
    "--angle",
    type=FINITE,  # the range (0, 90] is checked with the other render parameters
    default=None,
    help="Side-view elevation in degrees, in (0, 90] (default: the params' theta).",
)
@click.option(
    "--params",
    "params_file",
    type=InputFile("render parameters"),
    default=None,
    help="Renderer parameters JSON (heights, unit length, theta, shading); see docs/render.md.",
)
@click.option(
    "--tall-bumps",
    is_flag=True,
    help="The pattern is knitted with tall bumps (illuknit knit --tall-bumps): render its bumps "
    "at the params' tall_bump_height (docs/split-bumps.md).",
)
@click.option(
    "--scale",
    type=click.IntRange(1, 64),
    default=None,
    help="Pixels per unit (default: about 640 px on the long side).",
)
@click.option(
    "--frames",
    type=click.IntRange(2, 400),
    default=31,
    show_default=True,
    help="GIF frames from one side to the other.",
)
@outdir_option()
def render(
    pattern_file: Path,
    angle: float | None,
    params_file: Path | None,
    tall_bumps: bool,
    scale: int | None,
    frames: int,
    outdir: Path,
) -> None:
    """Render PATTERN as a person sees it: view A (from above), view B (from below) and head-on
    PNGs, a contact sheet, and sweep.gif walking from one side through head-on to the other."""
    from illuknit.core.files import staged_dir
    from illuknit.core.machine import resolve_machine
    from illuknit.core.pattern import load_pattern
    from illuknit.design.render.params import RenderParams, check_angle, load_params, save_params
    from illuknit.outputs.previews import contact_sheet, save_png, unit_scale

    params = load_params(params_file) if params_file is not None else RenderParams()
    if tall_bumps:
        params = params.with_tall_bumps()
    a = check_angle(params.theta if angle is None else angle, name="--angle")
    params = params.with_angle(a)
    pattern = load_pattern(pattern_file)
    s = scale or min(64, max(2, unit_scale(pattern.shape)))  # --scale's own range
    check_render_size(pattern.shape, scale=s, frames=frames)
    # drawn in the fabric's proportions (the default machine's gauge), foreshortened as seen
    aspect = resolve_machine(None).fabric_gauge.unit_aspect
    views, images = _render_all(pattern, a, params=params, scale=s, frames=frames, aspect=aspect)
    with staged_dir(outdir) as tmp:
        for name, img in views.items():
            save_png(img, tmp / f"{name}.png")
        sheet = contact_sheet(
            [
                (f"view A (from above, {a:g} deg)", views["view_a"]),
                ("head-on", views["headon"]),
                (f"view B (from below, {a:g} deg)", views["view_b"]),
            ]
        )
        save_png(sheet, tmp / "contact.png")
        _save_gif(images, tmp / "sweep.gif")
        save_params(params, tmp / "params.json")
        written = sorted(p.name for p in tmp.iterdir())
    click.echo(f"wrote {len(written)} files to {outdir}: {', '.join(written)}")


def _render_all(
    pattern: Any, a: float, *, params: Any, scale: int, frames: int, aspect: float
) -> tuple[dict[str, Any], list[Any]]:
    """The three views and the sweep's frames (A -> head-on -> B and back, so the loop has no
    jump), each frame on a canvas as tall as head-on: a piece seen from lower down is shorter."""
    from illuknit.core.progress import progress
    from illuknit.design.render.raycast import render_image, sweep_angles

    angles = sweep_angles(a, frames)
    with progress(3 + len(angles), "render") as advance:
        views = {}
        for name, at in (("view_a", a), ("view_b", -a), ("headon", 90.0)):
            views[name] = render_image(pattern, at, params=params, scale=scale, unit_aspect=aspect)
            advance(description=name)
        height = views["headon"].shape[0]
        # Each frame is kept as a palette frame (1 byte per pixel), not as RGB.
        images = []
        for x in angles:
            img = render_image(pattern, x, params=params, scale=scale, unit_aspect=aspect)
            images.append(_gif_frame(_on_canvas(img, height)))
            advance(description=f"sweep {x:+.0f} deg")
    images += images[-2:0:-1]
    return views, images


def _on_canvas(img: Any, height: int) -> Any:
    """``img`` centred vertically on a white canvas ``height`` rows tall."""
    import numpy as np

    canvas = np.full((max(height, img.shape[0]), *img.shape[1:]), 255, dtype=np.uint8)
    top = (canvas.shape[0] - img.shape[0]) // 2
    canvas[top : top + img.shape[0]] = img
    return canvas


def _gif_frame(rgb: Any) -> Any:
    from PIL import Image

    return Image.fromarray(rgb).convert("P", palette=Image.Palette.ADAPTIVE, colors=64)


def _save_gif(frames: list, path: Path) -> None:
    n = len(frames)
    # Hold the two side views and head-on a little longer than the frames in between.
    half = (n + 2) // 4
    durations = [500 if i in (0, half, 2 * half) else 60 for i in range(n)]
    frames[0].save(
        path, save_all=True, append_images=frames[1:], duration=durations, loop=0, disposal=1
    )
