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


#: The fields declared on the library's option classes: (model, field, class, option).
DECLARED = (
    ("DesignSettings", "candidates", "illuknit.design.options.SearchOptions", "candidates"),
    ("DesignSettings", "split_bumps", "illuknit.design.options.SearchOptions", "split_bumps"),
    ("DesignSettings", "view_angle", "illuknit.design.options.RankOptions", "angle"),
    ("DesignSettings", "view_distance", "illuknit.design.options.RankOptions", "distance"),
    ("JobIn", "allow_long_floats", "illuknit.knit.options.KnitOptions", "allow_long_floats"),
)


@pytest.mark.parametrize(("model", "field", "cls", "name"), DECLARED)
def test_declared_fields_take_the_library_s_default_and_no_wider_range(model, field, cls, name):
    import importlib

    from illuknit.app import schemas
    from illuknit.core.declared import declared_options

    module, _, cls_name = cls.rpartition(".")
    opt = declared_options(getattr(importlib.import_module(module), cls_name))[name]
    info = getattr(schemas, model).model_fields[field]
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
