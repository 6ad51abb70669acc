"""The knitting options: one frozen, validated type for every switch of the knitting path.

:class:`KnitOptions` is what :func:`~illuknit.knitting.pipeline.knit_pattern`, ``illuknit knit``,
the ``--knitout`` options of the design commands and the app pass on; it is checked once, where
it is made, so a bad value is refused before any work starts. The choices are enums, not
strings: :class:`Catching` (how neighbouring carriers' regions are joined) and
:class:`PathPlanning` (the yarn-path strategy of the mixed-colourwork scheduler). Their values
are the words the CLI takes, so ``Catching("plate")`` reads a command-line value.

Examples
--------
>>> KnitOptions().catching
<Catching.TUCK: 'tuck'>
>>> KnitOptions(catching="plate", path_planning="split").path_planning
<PathPlanning.SPLIT: 'split'>
>>> KnitOptions(catch_every=0)
Traceback (most recent call last):
...
illuknit.core.errors.OptionError: `catch_every` must be a positive integer, got 0
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from illuknit.core.arguments import check_int
from illuknit.core.declared import check_declared_range, option
from illuknit.core.errors import OptionError
from illuknit.design.options import MAX_COUNT, count_option, enum_option, flag_option

__all__ = ["Catching", "KnitOptions", "PathPlanning"]


class Catching(StrEnum):
    """How the mixed-colourwork scheduler joins neighbouring carriers' regions.

    ``TUCK`` (the default): a carrier tucks on the neighbour's edge needle in its own pass,
    plated stitches only where no tuck is safe; ``PLATE``: the paper's plated stitches
    everywhere (Algorithm 2); ``OFF``: no joins (the paper's ablation).
    """

    TUCK = "tuck"
    PLATE = "plate"
    OFF = "off"


class PathPlanning(StrEnum):
    """The yarn-path strategy (paper Algorithm 3) of the mixed-colourwork scheduler; ``NONE``
    knits every pass in the course's parity direction (the ablation)."""

    ANCHOR = "anchor"
    SPLIT = "split"
    NONE = "none"


@dataclass(frozen=True)
class KnitOptions:
    """How a pattern is knit (the machine is given beside it, by name or spec).

    Parameters
    ----------
    cast_on_courses : int
        Plain courses between the cast-on and the pattern (0 to 100).
    float_avoidance : bool
        Move purls to the front around floats that cross them (paper Algorithm 1).
    catching : Catching or str
        How neighbouring carriers' regions are joined (:class:`Catching`); the strings
        ``"tuck"``, ``"plate"`` and ``"off"`` are read as the members.
    path_planning : PathPlanning or str
        Yarn-path strategy (:class:`PathPlanning`).
    catch_every : int
        Join on every ``catch_every``-th course. 2: once per unit row (a unit is two courses), so
        no join stays open for more than one course; 1: at every colour change of every course,
        as the paper does, at the price of more passes.
    strict_floats : bool
        Refuse a course that needs more carriers than the machine has to keep every float
        within the limit.
    tuck_passes : bool
        Where a plated catching pass cannot tuck a long float (its other yarn comes from
        elsewhere), tuck the floating yarn alone in a pass of its own right before it. It
        matters with ``catching="plate"`` only (on the plated bundled programs it cost 1-29 %
        more machine passes, ``docs/mixed-colourwork.md``).
    allow_long_floats : bool
        Keep a float that stays longer than the machine's float limit after tucking (with a
        warning) instead of refusing the pattern.
    tall_bumps : bool
        Add yarn to every raised unit: each purl of a bump is preceded by a tuck on its needle,
        in a pass of its own, which the purl knits through (``docs/split-bumps.md``). One more
        carriage pass per carrier in every course that purls; off by default.

    The six before ``tall_bumps`` apply to patterns that change colour inside a course (the
    mixed-colourwork scheduler) only.
    """

    cast_on_courses: int = option(
        2, help="Plain courses between the cast-on and the pattern.", ge=0, le=100
    )
    float_avoidance: bool = option(
        True, help="Move purls to the front around floats that cross them (the default)."
    )
    catching: Catching = option(
        Catching.TUCK,
        help="How neighbouring carriers' regions are joined: tuck joins, the paper's plated "
        "stitches (Algorithm 2), or off (the Fig. 20 ablation).",
    )
    path_planning: PathPlanning = option(
        PathPlanning.ANCHOR,
        help="Yarn path strategy (paper Algorithm 3); 'none' is the Fig. 20 ablation.",
    )
    catch_every: int = option(
        2,
        help="Join colour regions on every N-th course (1 = every course, as in the paper).",
        ge=1,
        le=MAX_COUNT,
    )
    strict_floats: bool = option(
        False,
        help="Also fail when a course needs more carriers than the machine has to keep floats "
        "within the limit (default: bridge the shortest gaps with longer floats, then tuck them).",
    )
    tuck_passes: bool = option(
        False,
        help="Tuck a long float of a plated catching pass in a pass of the floating yarn alone "
        "(fewer long floats, more passes; default: keep them and warn).",
    )
    allow_long_floats: bool = option(
        False,
        help="Knit a mixed-colourwork piece even where a float stays longer than the machine's "
        "float limit after tucking (a course with more colour regions than carriers), with a "
        "warning saying how long and where (default: refuse, naming the course and what to "
        "change).",
    )
    tall_bumps: bool = option(
        False,
        help="Taller bumps: tuck each bump's purl needle in a pass of its own before the purl "
        "(more yarn in every raised unit, one more pass per carrier in each purl course; "
        "docs/split-bumps.md). Measure the new bump height with 'illuknit calibrate swatch "
        "--tall-bumps'.",
    )

    def __post_init__(self) -> None:
        check_int(self.cast_on_courses, "cast_on_courses")
        check_declared_range(KnitOptions, "cast_on_courses", self.cast_on_courses, OptionError)
        count_option("catch_every", self.catch_every, minimum=1)
        check_declared_range(KnitOptions, "catch_every", self.catch_every, OptionError)
        for name in (
            "float_avoidance",
            "strict_floats",
            "tuck_passes",
            "allow_long_floats",
            "tall_bumps",
        ):
            flag_option(name, getattr(self, name))
        object.__setattr__(self, "catching", enum_option(Catching, "catching", self.catching))
        object.__setattr__(
            self, "path_planning", enum_option(PathPlanning, "path_planning", self.path_planning)
        )
