"""On the quick bundled instances, the default design reads at least as well as every other one
written, measured again by the stage a user interface measures a design with
(:func:`illuknit.pipeline.stages.measure_design`) at the ranking's viewing angle and distance.

(``benchmarks/measure_choice.py`` prints the same for every bundled instance, with the default
pool, and compares the measure with the candidates it was chosen over.)"""

from __future__ import annotations

import numpy as np
import pytest

from illuknit.bench.instances import instance_targets, load_manifest
from illuknit.design.options import RankOptions, SearchOptions
from illuknit.pipeline.stages import design_double, design_headon, measure_design

QUICK_TWO_YARN = ["plus-circle", "heart-ecg", "illusion-knitting-small"]


def _pictures(name: str):
    inst = next(i for i in load_manifest().instances if i.name == name)
    t = instance_targets(inst)
    rgb = [np.round(np.asarray(t.rgb(v), float) * 255).astype(np.uint8) for v in "AB"]
    return inst, rgb


@pytest.mark.parametrize("name", QUICK_TWO_YARN)
@pytest.mark.parametrize("mode", ["double", "headon"])
def test_the_default_reads_at_least_as_well_as_every_other_written(name, mode):
    inst, (a, b) = _pictures(name)
    # seen from 40 m at a steeper angle than the default: the ranking's own viewpoint is used
    ranking = RankOptions(angle=40.0, distance=40.0)
    kw = dict(
        n_colors=2,
        yarns=inst.yarns,
        width=inst.size[1] // 2,
        search=SearchOptions(candidates=3, pool=3),
        ranking=ranking,
    )
    design = design_double(a, b, **kw) if mode == "double" else design_headon(a, **kw)
    qa, qb = design.quantised["A"], design.quantised.get("B")
    again = [measure_design(d.pattern, mode, qa, qb, ranking=ranking) for d in design.designs]
    assert [d.measures for d in design.designs] == again  # the ranking measured them so
    best = again[0].perceptual_score
    assert all(best >= m.perceptual_score for m in again[1:]), [m.perceptual_score for m in again]
    # and the viewpoint counts: the same designs judged from elsewhere measure differently
    near = measure_design(design.designs[0].pattern, mode, qa, qb, ranking=RankOptions())
    assert near != again[0]
