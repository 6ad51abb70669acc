"""Benchmark instances: the TOML manifest, its validation, and the target images it describes.

A manifest (``instances/manifest.toml`` in the source tree) is a list of ``[[instance]]`` tables::

    [[instance]]
    name = "heart-ecg"            # unique, [a-z0-9-]
    kind = "double"               # "double" (view A and view B differ) or "single"
    size = [40, 40]               # [rows, cols] in units
    yarns = ["#1b1b1b", "#f4f0e8"]
    time_limit = 10               # seconds per solve (the CLI's --time-limit overrides it)
    tags = ["quick"]              # "quick" puts it in the quick subset
    a = { draw = "heart" }        # target of view A (double) ...
    b = { draw = "ecg" }          # ... and of view B; a single-view instance has `input` instead

An input is exactly one of

* ``{ draw = "heart" | "ecg" | "plus" | "circle" }`` — a shape from :mod:`illuknit.pictures.drawings`;
* ``{ text = "ILLUSION" }`` — text in Pillow's bundled font;
* ``{ image = "coffee" }`` — a scikit-image bundled picture, quantised to the instance's yarns;
* ``{ layers = [{ draw = "circle", yarn = 2 }, { text = "A", yarn = 1 }], background = 0 }`` —
  masks painted in order over a background yarn.

Masks (``draw``/``text``) become yarn ``ink`` (default 0) on yarn ``paper`` (default 1);
``invert = true`` swaps them. Everything is drawn by code; nothing needs the network.
"""

from __future__ import annotations

import hashlib
import json
import re
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from illuknit.core.errors import ImageInputError, ManifestError, UnknownNameError, YarnSpecError
from illuknit.core.pattern import MAX_UNITS, Yarn, parse_yarns
from illuknit.solvers.model import Model

__all__ = [
    "DEFAULT_MANIFEST",
    "KINDS",
    "Instance",
    "Manifest",
    "Targets",
    "instance_model",
    "instance_targets",
    "load_manifest",
    "parse_manifest",
    "select_instances",
]

KINDS = ("double", "single")
#: Smallest side accepted in a manifest (tests use tiny instances; real ones start at 30).
MIN_SIDE = 4
_NAME = re.compile(r"^[a-z0-9][a-z0-9-]*$")
_INSTANCE_KEYS = {"name", "kind", "size", "yarns", "time_limit", "tags", "a", "b", "input", "notes"}
_INPUT_KEYS = {"draw", "text", "image", "layers", "background", "ink", "paper", "invert", "yarn"}


def _default_manifest() -> Path:
    # The subpackage illuknit.instances: the top-level instances/ folder, installed inside the
    # package (pyproject's package-dir) or found in a checkout (illuknit.core.source_tree).
    from importlib import resources

    return Path(str(resources.files("illuknit.instances") / "manifest.toml"))


#: The manifest shipped in the source tree (``instances/manifest.toml``).
DEFAULT_MANIFEST = _default_manifest()


@dataclass(frozen=True)
class Instance:
    """One benchmark instance (validated; see the module docstring for the fields).

    ``inputs`` maps ``"A"`` and ``"B"`` (double) or ``"A"`` alone (single) to the input spec.
    """

    name: str
    kind: str
    size: tuple[int, int]
    yarns: tuple[Yarn, ...]
    time_limit: float
    inputs: Mapping[str, Mapping[str, Any]]
    tags: tuple[str, ...] = ()
    notes: str = ""

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ManifestError(f"instance {self.name!r}: `kind` must be one of {KINDS}")
        want = ("A", "B") if self.kind == "double" else ("A",)
        if tuple(sorted(self.inputs)) != want:
            raise ManifestError(f"instance {self.name!r}: inputs must be {want}")

    @property
    def quick(self) -> bool:
        return "quick" in self.tags

    def spec(self) -> dict[str, Any]:
        """A plain JSON-able description (what the results record and the cell key hashes)."""
        return {
            "name": self.name,
            "kind": self.kind,
            "size": list(self.size),
            "yarns": [y.hex for y in self.yarns],
            "time_limit": self.time_limit,
            "inputs": {k: dict(v) for k, v in sorted(self.inputs.items())},
        }

    def to_manifest(self) -> dict[str, Any]:
        """This instance as a manifest table (``parse_manifest({"instance": [t]})`` reads it back)."""
        entry: dict[str, Any] = {
            "name": self.name,
            "kind": self.kind,
            "size": list(self.size),
            "yarns": [y.hex for y in self.yarns],
            "time_limit": self.time_limit,
            "tags": list(self.tags),
        }
        if self.kind == "double":
            entry["a"], entry["b"] = dict(self.inputs["A"]), dict(self.inputs["B"])
        else:
            entry["input"] = dict(self.inputs["A"])
        return entry

    def key(self) -> str:
        """Short content hash of :meth:`spec` (changes whenever the instance changes)."""
        text = json.dumps(self.spec(), sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:16]


@dataclass(frozen=True)
class Manifest:
    """A validated manifest: instances in file order, and where it came from."""

    instances: tuple[Instance, ...]
    path: str = ""

    def names(self) -> list[str]:
        return [i.name for i in self.instances]

    def get(self, name: str) -> Instance:
        for inst in self.instances:
            if inst.name == name:
                return inst
        raise UnknownNameError("instance", name, self.names())


def _fail(where: str, message: str) -> ManifestError:
    return ManifestError(f"{where}: {message}")


def _check_input(where: str, spec: Any, n_yarns: int, *, layer: bool = False) -> dict[str, Any]:
    from illuknit.pictures.drawings import BUNDLED_IMAGES, DRAWINGS

    if not isinstance(spec, Mapping):
        raise _fail(where, f'must be a table such as {{ draw = "heart" }}, got {spec!r}')
    unknown = set(spec) - _INPUT_KEYS
    if unknown:
        raise _fail(where, f"unknown key(s) {sorted(unknown)}; valid: {sorted(_INPUT_KEYS)}")
    sources = [k for k in ("draw", "text", "image", "layers") if k in spec]
    if len(sources) != 1:
        raise _fail(where, "needs exactly one of draw, text, image, layers")
    src = sources[0]
    if src == "draw" and spec["draw"] not in DRAWINGS:
        raise _fail(
            where, f"unknown drawing {spec['draw']!r}; valid: {', '.join(sorted(DRAWINGS))}"
        )
    if src == "text" and (not isinstance(spec["text"], str) or not spec["text"].strip()):
        raise _fail(where, "`text` must be a non-empty string")
    if src == "image":
        if layer:
            raise _fail(where, "a layer must be a drawing or text, not an image")
        if spec["image"] not in BUNDLED_IMAGES:
            raise _fail(
                where,
                f"input image {spec['image']!r} is not a bundled scikit-image picture; valid: "
                + ", ".join(sorted(BUNDLED_IMAGES)),
            )
    if src == "layers":
        if layer:
            raise _fail(where, "layers cannot nest")
        layers = spec["layers"]
        if not isinstance(layers, list) or not layers:
            raise _fail(where, "`layers` must be a non-empty list of tables")
        for i, lay in enumerate(layers):
            _check_input(f"{where}.layers[{i}]", lay, n_yarns, layer=True)
            if "yarn" not in lay:
                raise _fail(f"{where}.layers[{i}]", "each layer needs a `yarn` index")
    for key in ("background", "ink", "paper", "yarn"):
        if key in spec:
            v = spec[key]
            if not isinstance(v, int) or isinstance(v, bool) or not 0 <= v < n_yarns:
                raise _fail(where, f"`{key}` must be a yarn index in 0..{n_yarns - 1}, got {v!r}")
    if "invert" in spec and not isinstance(spec["invert"], bool):
        raise _fail(where, "`invert` must be true or false")
    return dict(spec)


def _check_instance(i: int, raw: Any) -> Instance:
    if not isinstance(raw, Mapping):
        raise ManifestError(f"instance #{i + 1}: must be a table")
    name = raw.get("name")
    if not isinstance(name, str) or not _NAME.match(name):
        raise ManifestError(f"instance #{i + 1}: `name` must match [a-z0-9-]+, got {name!r}")
    where = f"instance {name!r}"
    unknown = set(raw) - _INSTANCE_KEYS
    if unknown:
        raise _fail(where, f"unknown key(s) {sorted(unknown)}; valid: {sorted(_INSTANCE_KEYS)}")
    kind = raw.get("kind", "double")
    if kind not in KINDS:
        raise _fail(where, f"`kind` must be one of {', '.join(KINDS)}, got {kind!r}")
    size = raw.get("size")
    if (
        not isinstance(size, list | tuple)
        or len(size) != 2
        or not all(isinstance(v, int) and not isinstance(v, bool) for v in size)
        or not all(MIN_SIDE <= v <= MAX_UNITS for v in size)
    ):
        raise _fail(
            where,
            f"`size` must be [rows, cols] with integers in {MIN_SIDE}..{MAX_UNITS}, got {size!r}",
        )
    try:
        yarns = parse_yarns(raw.get("yarns") or [])
    except YarnSpecError as e:
        raise _fail(where, f"`yarns`: {e}") from None
    if not 2 <= len(yarns) <= 6:
        raise _fail(where, f"`yarns` must list 2..6 colours, got {len(yarns)}")
    tl = raw.get("time_limit", 30)
    if not isinstance(tl, int | float) or isinstance(tl, bool) or not tl > 0:
        raise _fail(where, f"`time_limit` must be a positive number of seconds, got {tl!r}")
    tags = raw.get("tags", [])
    if not isinstance(tags, list) or not all(isinstance(t, str) for t in tags):
        raise _fail(where, "`tags` must be a list of strings")
    if kind == "double":
        for key in ("a", "b"):
            if key not in raw:
                raise _fail(
                    where,
                    f"a double-view instance needs input `{key}` (the view {key.upper()} target)",
                )
        if "input" in raw:
            raise _fail(where, "a double-view instance takes `a` and `b`, not `input`")
        inputs = {
            "A": _check_input(f"{where}.a", raw["a"], len(yarns)),
            "B": _check_input(f"{where}.b", raw["b"], len(yarns)),
        }
    else:
        if "input" not in raw:
            raise _fail(where, "a single-view instance needs `input`")
        if "a" in raw or "b" in raw:
            raise _fail(where, "a single-view instance takes `input`, not `a`/`b`")
        inputs = {"A": _check_input(f"{where}.input", raw["input"], len(yarns))}
    return Instance(
        name=name,
        kind=kind,
        size=(int(size[0]), int(size[1])),
        yarns=yarns,
        time_limit=float(tl),
        inputs=inputs,
        tags=tuple(tags),
        notes=str(raw.get("notes", "")),
    )


def parse_manifest(data: Mapping[str, Any], *, path: str = "") -> Manifest:
    """Validate a parsed TOML document (a mapping with an ``instance`` array of tables)."""
    raw = data.get("instance")
    if not isinstance(raw, list) or not raw:
        raise ManifestError(f"{path or 'manifest'}: needs at least one [[instance]] table")
    instances = [_check_instance(i, r) for i, r in enumerate(raw)]
    seen: set[str] = set()
    for inst in instances:
        if inst.name in seen:
            raise ManifestError(f"instance {inst.name!r} is defined twice")
        seen.add(inst.name)
    return Manifest(tuple(instances), path=path)


def load_manifest(path: str | Path | None = None) -> Manifest:
    """Read and validate a manifest file (default: :data:`DEFAULT_MANIFEST`).

    Raises
    ------
    ManifestError
        Missing or unparseable file, or an invalid entry (the message names it).
    """
    from illuknit.core.documents import read_text_file

    p = Path(path) if path is not None else DEFAULT_MANIFEST
    text = read_text_file(p, error=ManifestError, what="manifest")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ManifestError(f"manifest {str(p)!r} is not valid TOML: {e}") from None
    return parse_manifest(data, path=str(p))


def select_instances(
    manifest: Manifest, selection: str | Sequence[str] = "quick"
) -> list[Instance]:
    """Instances named by ``selection``: ``"quick"``, ``"all"``, or names (comma-separated string
    or list; ``quick``/``all`` may be mixed in). Unknown names raise an error listing valid ones."""
    names = (
        [s.strip() for s in selection.split(",")] if isinstance(selection, str) else list(selection)
    )
    names = [n for n in names if n]
    if not names:
        raise UnknownNameError("instance", "", ["quick", "all", *manifest.names()])
    chosen: dict[str, Instance] = {}
    for n in names:
        if n == "all":
            group = list(manifest.instances)
        elif n == "quick":
            group = [i for i in manifest.instances if i.quick]
        else:
            try:
                group = [manifest.get(n)]
            except UnknownNameError:
                raise UnknownNameError("instance", n, ["quick", "all", *manifest.names()]) from None
        for inst in group:
            chosen.setdefault(inst.name, inst)
    order = {n: k for k, n in enumerate(manifest.names())}
    return sorted(chosen.values(), key=lambda i: order[i.name])


@dataclass(frozen=True, eq=False)
class Targets:
    """The target images of an instance, as yarn indices into ``yarns``.

    Attributes
    ----------
    a, b : ndarray of int16, shape (N, M)
        Targets of view A and view B (the same array for a single-view instance).
    yarns : tuple of Yarn
    """

    a: NDArray[np.int16]
    b: NDArray[np.int16]
    yarns: tuple[Yarn, ...]
    meta: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for name in ("a", "b"):
            arr = np.array(getattr(self, name), dtype=np.int16)
            if arr.ndim != 2 or arr.shape != np.shape(self.a):
                raise ImageInputError(f"`{name}` must be 2-D of shape {np.shape(self.a)}")
            if arr.min() < 0 or arr.max() >= len(self.yarns):
                raise ImageInputError(f"`{name}` indices must lie in 0..{len(self.yarns) - 1}")
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    @property
    def palette(self) -> NDArray[np.uint8]:
        """ndarray of shape (K, 3): yarn colours."""
        return np.array([y.rgb for y in self.yarns], dtype=np.uint8)

    def rgb(self, view: str) -> NDArray[np.float64]:
        """Target of ``view`` ("A" or "B") in yarn colours, float sRGB of shape (N, M, 3)."""
        idx = self.a if view == "A" else self.b
        return self.palette[idx].astype(np.float64) / 255.0


def _draw_input(spec: Mapping[str, Any], shape: tuple[int, int], yarns: tuple[Yarn, ...]):
    from illuknit.pictures.drawings import (
        draw_shape,
        draw_text,
        layer_masks,
        skimage_image,
        to_index_image,
    )

    def mask(s: Mapping[str, Any]) -> NDArray[np.bool_]:
        if "draw" in s:
            return draw_shape(s["draw"], shape)
        return draw_text(s["text"], shape=shape)

    if "image" in spec:
        from illuknit.pictures.images import quantise_image

        rgb = skimage_image(spec["image"], shape)
        q = quantise_image(rgb, yarns=yarns, n_colors=len(yarns))
        # quantise_image keeps only the yarns it used; map back to the instance's yarn indices.
        used = [next(i for i, y in enumerate(yarns) if y.rgb == u.rgb) for u in q.yarns]
        return np.asarray(used, dtype=np.int16)[q.indices]
    if "layers" in spec:
        masks = [mask(layer) for layer in spec["layers"]]
        return layer_masks(
            masks,
            background=int(spec.get("background", len(yarns) - 1)),
            indices=[int(layer["yarn"]) for layer in spec["layers"]],
        )
    return to_index_image(
        mask(spec),
        ink=int(spec.get("ink", 0)),
        paper=int(spec.get("paper", 1)),
        invert=bool(spec.get("invert", False)),
    )


_TARGETS: dict[str, Targets] = {}


def instance_targets(instance: Instance) -> Targets:
    """Draw (or load and quantise) the targets of ``instance``; cached per instance content."""
    key = instance.key()
    if key not in _TARGETS:
        a = _draw_input(instance.inputs["A"], instance.size, instance.yarns)
        b = a
        if instance.kind == "double":
            b = _draw_input(instance.inputs["B"], instance.size, instance.yarns)
        if len(_TARGETS) > 64:
            _TARGETS.clear()
        _TARGETS[key] = Targets(a, b, instance.yarns, {"instance": instance.name})
    return _TARGETS[key]


def stage_arguments(instance: Instance) -> tuple[Any, Any, dict[str, Any]]:
    """The pipeline stages' arguments that reproduce ``instance``'s targets exactly: the
    pictures (B None for a single-view instance) drawn in the yarns' own colours, taken unit
    for unit (square units, the grid's width, no quantisation) onto the instance's yarns.

    :func:`illuknit.pipeline.stages.solve_design` and :func:`~illuknit.pipeline.stages.illusion_model`
    called with them build the model of :func:`instance_targets` (a yarn neither target uses
    is left out, as for any picture)."""
    t = instance_targets(instance)
    rgb_b = None if instance.kind == "single" else t.palette[t.b]
    kw = {"yarns": instance.yarns, "quantise": False, "unit_aspect": 1.0, "width": t.a.shape[1]}
    return t.palette[t.a], rgb_b, kw


def instance_model(instance: Instance, *, model: str) -> tuple[Model, int | None]:
    """The constraint model of ``instance`` (the pipeline's
    :func:`~illuknit.pipeline.stages.illusion_model` on :func:`stage_arguments`) and its
    known optimum.

    Parameters
    ----------
    instance : Instance
    model : str
        Illusion model of a double-view instance (``"logical"``, ``"knit-aware"``); a single-view
        instance always gets the single-view model.

    Returns
    -------
    (Model, int or None)
        The model, and the DP's optimum where the DP is exact on it (else None).
    """
    from illuknit.design.models.backends.dp import solve_dp
    from illuknit.design.models.illusion_problem import problem_of
    from illuknit.design.options import ModelKind, SolveOptions
    from illuknit.pipeline.stages import illusion_model

    kind = "single" if instance.kind == "single" else model
    a, b, kw = stage_arguments(instance)
    built = illusion_model(a, b, options=SolveOptions(model=ModelKind(kind)), **kw)
    problem = problem_of(built)
    optimum = solve_dp(problem)[2] if (problem.per_wale or problem.rows_tied) else None
    return built, optimum
