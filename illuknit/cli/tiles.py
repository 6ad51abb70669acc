"""``illuknit tiles``: list a tile bank with its fills and draw every tile."""

from __future__ import annotations

import json
from pathlib import Path

import click
import numpy as np
from numpy.typing import NDArray

from illuknit.cli.options import InputFile, outdir_option
from illuknit.design.tiles.bank import TileBank
from illuknit.design.tiles.tile import Tile

__all__ = ["tile_picture", "tiles"]

DEFAULT_YARNS = "black=#1b1b1b,white=#f4f0e8"


def tile_picture(
    tile: Tile, bank: TileBank, *, periods: int = 2, cell: int = 20
) -> NDArray[np.uint8]:
    """One picture of a tile (Fig. 10 style): top-down with bumps marked, height map, view A,
    view B; each over ``periods`` repeats."""
    from illuknit.core.pattern import LogicalPattern
    from illuknit.design.tiles.tile import tile_seen
    from illuknit.outputs.previews import chart_rgb, contact_sheet, upscale

    # repeat across too, so each panel is wide enough for its title
    across = max(1, -(-5 // tile.width))
    yarn = np.tile(tile.yarn, (periods, across))
    raised = np.tile(tile.raised, (periods, across))
    p = LogicalPattern(yarn, raised, bank.yarns)
    pal = p.palette
    height = np.where(raised[..., None], 235, 60).astype(np.uint8).repeat(3, axis=2)
    va = pal[np.tile(tile_seen(tile, "A"), (periods, across))]
    vb = pal[np.tile(tile_seen(tile, "B"), (periods, across))]
    panels = [
        ("top-down", chart_rgb(p, scale=cell)),
        ("height", upscale(height, cell)),
        ("view A", upscale(va, cell)),
        ("view B", upscale(vb, cell)),
    ]
    # a grey frame, so white yarn stays visible on the white sheet
    framed = [
        (title, np.pad(img, ((1, 1), (1, 1), (0, 0)), constant_values=150)) for title, img in panels
    ]
    return contact_sheet(framed, pad=8)


@click.command("tiles")
@click.option(
    "--yarns",
    default=DEFAULT_YARNS,
    show_default=True,
    metavar="LIST",
    help="Yarn colours the bank is generated for (or that a --bank file's indices refer to).",
)
@click.option(
    "--bank",
    "bank_file",
    type=InputFile("tile bank"),
    default=None,
    help="A custom tile bank (JSON, see docs/tiles.md) instead of the canonical one.",
)
@click.option(
    "--headon", is_flag=True, help="The bank of the head-on variant (fills head-on / both sides)."
)
@click.option("--one-sided", is_flag=True, help="Only tiles that are solid from at least one side.")
@click.option(
    "--max-height", type=click.IntRange(1, 6), default=4, show_default=True, help="Tallest tile."
)
@outdir_option(
    required=False,
    help="Write bank.json and one picture per tile (top-down, height map, both side views) here.",
)
def tiles(
    yarns: str,
    bank_file: Path | None,
    headon: bool,
    one_sided: bool,
    max_height: int,
    outdir: Path | None,
) -> None:
    """Print a tile bank with the fills of every tile, and draw the tiles.

    Fills are computed with can_see over the tile's periodic extension: "black 2/3 + white 1/3"
    is a stripe with two black courses for one white one.
    """
    from rich.console import Console
    from rich.table import Table

    from illuknit.core.files import atomic_write_text, staged_dir
    from illuknit.core.pattern import parse_yarns
    from illuknit.core.progress import run_with_bar
    from illuknit.design.tiles.bank import bank_to_json, canonical_bank, load_bank
    from illuknit.outputs.previews import save_png

    ys = parse_yarns(yarns)
    views = ("headon", "side") if headon else ("A", "B")
    if bank_file is not None:
        bank = load_bank(bank_file, yarns=ys)
    else:
        bank = run_with_bar(
            "tiles",
            "enumerating the tiles and their fills",
            canonical_bank,
            ys,
            max_height=max_height,
            views=views,
            one_sided_stripes=one_sided,
        )
    con = Console(highlight=False, soft_wrap=True)
    table = Table(title=f"tile bank {bank.name!r}: {len(bank)} tiles", header_style="bold")
    for col in (
        "#",
        "tile (top row first, ^ = bump)",
        "h",
        "fill A (from above)",
        "fill B (from below)",
        "head-on",
    ):
        table.add_column(col)
    for k, (t, f) in enumerate(zip(bank.tiles, bank.fills, strict=True)):
        table.add_row(
            str(k),
            t.code(),
            str(t.height),
            *(f[v].label(bank.yarns) if f[v] is not None else "-" for v in ("A", "B", "headon")),  # type: ignore[union-attr]
        )
    con.print(table)
    if outdir is None:
        return
    with staged_dir(outdir) as tmp:
        atomic_write_text(tmp / "bank.json", json.dumps(bank_to_json(bank), indent=1) + "\n")
        for k, t in enumerate(bank.tiles):
            code = t.code().replace("/", "-").replace("^", "b").replace(" ", "")
            save_png(tile_picture(t, bank), tmp / f"tile_{k:03d}_{code}.png")
    con.print(f"wrote bank.json and {len(bank)} tile pictures to [bold]{outdir}[/]")
