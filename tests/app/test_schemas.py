"""The settings patch is derived from the session's settings: same fields, same bounds."""

from __future__ import annotations

import pytest

pytest.importorskip(
    "pydantic", reason="the app extra is not installed: pip install 'illuknit[app]'"
)

from pydantic import ValidationError

from illuknit.app.schemas import DesignSettings, SettingsPatch


def test_patch_has_every_setting_optional():
    assert set(SettingsPatch.model_fields) == set(DesignSettings.model_fields)
    assert SettingsPatch().model_dump(exclude_none=True) == {}


def test_patch_and_settings_share_their_bounds():
    for key, info in DesignSettings.model_fields.items():
        patch = SettingsPatch.model_fields[key]
        assert patch.metadata == info.metadata, key
        assert patch.title == info.title and patch.description == info.description


@pytest.mark.parametrize(
    "bad",
    [{"width_units": 1}, {"gauge": float("nan")}, {"width_cm": float("inf")}, {"n_colors": 5}],
)
def test_both_refuse_the_same_values(bad):
    with pytest.raises(ValidationError):
        SettingsPatch.model_validate(bad)
    with pytest.raises(ValidationError):
        DesignSettings.model_validate(bad)


def test_settings_are_frozen_and_round_trip_through_json():
    s = DesignSettings()
    with pytest.raises(ValidationError):
        s.width_units = 10  # type: ignore[misc]
    assert DesignSettings.model_validate(s.to_json()) == s
