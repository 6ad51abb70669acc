"""The one way the suite finds the reference backends, and what a missing one does."""

from __future__ import annotations

import pytest

from tests.conftest import ORACLES, reference_backend


def test_a_missing_backend_skips_outside_ci(monkeypatch):
    monkeypatch.delenv("CI", raising=False)
    with pytest.raises(pytest.skip.Exception, match="missing"):
        reference_backend("no-such-backend.js")


def test_a_missing_backend_fails_under_ci(monkeypatch):
    monkeypatch.setenv("CI", "true")
    with pytest.raises(pytest.fail.Exception, match="under CI=true"):
        reference_backend("no-such-backend.js")


def test_the_backends_are_found_beside_the_checkout_or_where_the_variable_says(monkeypatch):
    import os
    from pathlib import Path

    expected = (
        os.environ.get("ILLUKNIT_ORACLES") or Path(__file__).parents[3] / "shared" / "oracles"
    )
    assert Path(expected).resolve() == ORACLES.resolve()
