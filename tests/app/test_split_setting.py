"""The app's split-bumps setting reaches the tile search."""

import numpy as np
import pytest

import illuknit.pipeline.stages as stages
from illuknit.app.candidates import make_candidates
from illuknit.app.inputs import Prepared
from illuknit.app.schemas import DesignSettings
from illuknit.core.pattern import parse_yarns
from illuknit.pictures.images import QuantisedImage


class _Searched(Exception):
    pass


@pytest.mark.parametrize("split", [False, True])
def test_split_bumps_setting_reaches_the_search(monkeypatch, split):
    assert DesignSettings().split_bumps is False  # off unless asked
    seen = []

    def fake_design_tiles(*args, search, **kw):
        seen.append(search)
        raise _Searched

    monkeypatch.setattr(stages, "design_tiles", fake_design_tiles)
    yarns = parse_yarns("#1b1b1b,#f4f0e8")
    pal = np.array([y.rgb for y in yarns], dtype=np.uint8)
    q = QuantisedImage(np.eye(4, dtype=int), yarns, pal)
    with pytest.raises(_Searched):
        make_candidates(
            Prepared("double", yarns, {"a": q, "b": q}),
            count=1,
            progress=lambda f, m: None,
            split_bumps=split,
        )
    assert seen[0].split_bumps is split
