"""The app's split-bumps setting reaches the tile search."""

import pytest

from illuknit.app.schemas import DesignSettings


@pytest.mark.parametrize("split", [False, True])
def test_split_bumps_setting_reaches_the_search(search_keywords, split):
    assert DesignSettings().split_bumps is False  # off unless asked
    assert search_keywords(split_bumps=split)["search"].split_bumps is split
