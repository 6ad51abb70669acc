"""The commands' options generated from the option classes' declarations match them: same
flag, default, range, choices and help; and a new declared field reaches the CLI and the app
with no other edit."""

from __future__ import annotations

from dataclasses import dataclass

import click
import pytest
from click.testing import CliRunner

from illuknit.cli import cli
from illuknit.cli.knitout_bridge import LONG_FLOATS_HELP
from illuknit.cli.options import FiniteFloat, options_from, options_of
from illuknit.core.declared import declared_options, option
from illuknit.design.options import Brightness, RankOptions, SearchOptions, SolveOptions
from illuknit.knit.options import KnitOptions

#: Which declared options each command generates, and from which class.
GENERATED = {
    "solve": (
        SolveOptions,
        ("solver", "warm_start", "model", "alternate_rows", "split_bumps", "time_limit", "seed"),
    ),
    "knit": (
        KnitOptions,
        ("cast_on_courses", "strict_floats", "tuck_passes", "tall_bumps", "catch_every"),
    ),
    "double": (
        SearchOptions,
        ("candidates", "pool", "solver", "one_sided", "split_bumps", "split_share"),
    ),
    "headon": (
        SearchOptions,
        ("candidates", "pool", "solver", "one_sided", "split_bumps", "split_share"),
    ),
    "double ": (RankOptions, ("rank_by", "made_for", "knit_time", "angle", "distance", "read")),
    "headon ": (RankOptions, ("rank_by", "made_for", "knit_time", "angle", "distance")),
    "legible": (RankOptions, ("angle", "distance")),
}
#: Options a command takes as "not given" (None) where the declaration has a default.
NOT_GIVEN = {"split_share", "read"}


def _range(param: click.Parameter) -> tuple[object, object, bool, bool]:
    t = param.type
    return (t.min, t.max, bool(t.min_open), bool(t.max_open))  # type: ignore[attr-defined]


def _check(param: click.Option, opt) -> None:
    assert opt.flag.split("/")[0] in param.opts, (param.opts, opt.flag)
    assert (param.help or "").startswith(opt.declared.help)
    if opt.name in NOT_GIVEN:
        assert param.default is None
    elif not param.is_flag or param.secondary_opts:
        assert param.default == opt.cli_default
        assert param.show_default
    else:
        assert opt.default is False  # a bare flag switches on what is off by default
    if opt.choices is not None:
        assert tuple(param.type.choices) == opt.choices  # type: ignore[attr-defined]
    low, high, low_open, high_open = opt.declared.bounds
    if opt.base_type is float:
        assert isinstance(param.type, FiniteFloat)
    if opt.base_type in (int, float):
        assert _range(param) == (low, high, low_open, high_open)


@pytest.mark.parametrize("command", list(GENERATED))
def test_generated_options_match_their_declarations(command):
    cls, names = GENERATED[command]
    cmd = cli.get_command(click.Context(cli), command.strip())
    params = {p.name: p for p in cmd.params}
    opts = declared_options(cls)
    for name in names:
        assert isinstance(params[name], click.Option), name
        _check(params[name], opts[name])


def test_the_long_floats_help_is_declared_once():
    assert declared_options(KnitOptions)["allow_long_floats"].declared.help == LONG_FLOATS_HELP


def test_options_from_makes_every_option_of_a_class():
    @click.command()
    @options_from(SolveOptions)
    def cmd(**kw):
        click.echo(repr(options_of(SolveOptions, kw)))

    flags = {o for p in cmd.params for o in p.opts}
    assert flags >= {opt.flag for opt in declared_options(SolveOptions).values()}
    run = CliRunner().invoke(cmd, ["--model", "single", "--alternate-rows", "--seed", "7"])
    assert run.exit_code == 0, run.output
    assert "seed=7" in run.output and "alternate_rows=True" in run.output
    bad = CliRunner().invoke(cmd, ["--time-limit", "0"])
    assert bad.exit_code == 2 and "0<x<=604800" in bad.output


def test_a_new_declared_field_reaches_the_cli_and_the_app_unedited():
    pytest.importorskip("pydantic")
    from pydantic import ValidationError, create_model

    from illuknit.app.schemas import declared_fields

    @dataclass(frozen=True)
    class Extended(KnitOptions):
        bobbles: int = option(3, help="Bobbles per repeat.", ge=1, le=9)

    @click.command()
    @options_from(Extended)
    def cmd(**kw):
        click.echo(repr(options_of(Extended, kw).bobbles))

    shown = CliRunner().invoke(cmd, ["--help"]).output
    assert "--bobbles" in shown and "Bobbles per repeat." in shown and "1<=x<=9" in shown
    assert CliRunner().invoke(cmd, ["--bobbles", "5"]).output.strip() == "5"
    assert CliRunner().invoke(cmd, ["--bobbles", "10"]).exit_code == 2

    model = create_model("ExtendedSettings", **declared_fields(Extended))
    assert model().bobbles == 3
    assert model.model_json_schema()["properties"]["bobbles"]["maximum"] == 9
    with pytest.raises(ValidationError):
        model(bobbles=10)
    assert model(catching="plate").catching == "plate"


@pytest.mark.parametrize("command", ["double", "headon"])
@pytest.mark.parametrize(
    ("argv", "soft", "warned"),
    [
        ([], False, False),
        (["--brightness", "soft"], True, False),
        (["--soft-brightness"], True, True),  # the old spelling, for one release
        (["--soft-brightness", "--brightness", "hard"], False, True),  # the new one wins
    ],
)
def test_soft_brightness_is_an_old_spelling_of_brightness_soft(
    command, argv, soft, warned, tmp_path, monkeypatch, run_cli
):
    import importlib

    seen = {}
    module = importlib.import_module(f"illuknit.cli.{command}")
    monkeypatch.setattr(module, "run_design", lambda request, **kw: seen.update(r=request) or {})
    monkeypatch.setattr(module, "print_summary", lambda *a: None)
    picture = tmp_path / "a.png"
    picture.write_bytes(b"")
    code, _, err = run_cli([command, picture, picture, *argv, "-o", tmp_path / "out"])
    assert code == 0, err
    assert seen["r"].search.brightness is (Brightness.SOFT if soft else Brightness.HARD)
    assert ("--soft-brightness is deprecated" in err) is warned, err
    assert "use --brightness soft" in err or not warned


def test_the_old_spelling_is_hidden_from_help():
    shown = CliRunner().invoke(cli, ["double", "--help"]).output
    assert "--brightness [hard|soft]" in shown and "--soft-brightness" not in shown


def test_calibrate_fit_takes_the_declared_split_share():
    group = cli.get_command(click.Context(cli), "calibrate")
    fit = group.get_command(click.Context(group), "fit")
    param = next(p for p in fit.params if p.name == "split_share")
    _check(param, declared_options(SearchOptions)["split_share"])
