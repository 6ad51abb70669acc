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


#: The settings declared on the library's option classes: (setting, class, option).
DECLARED = (
    ("candidates", "SearchOptions", "candidates"),
    ("split_bumps", "SearchOptions", "split_bumps"),
    ("view_angle", "RankOptions", "angle"),
    ("view_distance", "RankOptions", "distance"),
)


@pytest.mark.parametrize(("setting", "cls", "name"), DECLARED)
def test_declared_settings_take_the_library_s_default_and_no_wider_range(setting, cls, name):
    from illuknit.core.declared import declared_options
    from illuknit.design import options

    opt = declared_options(getattr(options, cls))[name]
    info = DesignSettings.model_fields[setting]
    assert info.default == opt.default
    assert info.title == opt.title
    for bound in info.metadata:  # every value the app takes, the library takes
        for key in ("ge", "gt", "le", "lt"):
            value = getattr(bound, key, None)
            if value is not None:
                assert opt.declared.contains(value) or value == getattr(opt.declared, key)


def test_a_declared_field_may_narrow_but_not_widen():
    from illuknit.app.schemas import declared_field
    from illuknit.design.options import SearchOptions

    assert declared_field(SearchOptions, "candidates", le=12).default == 5
    with pytest.raises(ValueError, match="does not narrow"):
        declared_field(SearchOptions, "candidates", le=60)
