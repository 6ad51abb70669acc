"""Bad input on every command: one line on stderr, exit code 2, nothing half-written.

Numeric options are checked once, by the option types of illuknit.cli.options, for all commands.
"""

import click
import numpy as np
import pytest
from PIL import Image

from illuknit.cli import COMMANDS, cli, main
from illuknit.cli.options import FiniteFloat


def assert_one_line(code, err, *needles):
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    for n in needles:
        assert n in lines[0], lines[0]


@pytest.fixture(scope="module")
def made(tmp_path_factory):
    """A picture, its single-view pattern and knitout program (made once for the module)."""
    d = tmp_path_factory.mktemp("inputs")
    rgb = np.full((12, 16, 3), 240, np.uint8)
    rgb[3:9, 4:12] = 20
    Image.fromarray(rgb).save(d / "pic.png")
    main(["single", str(d / "pic.png"), "--knitout", "-o", str(d / "made")])
    return {
        "PIC": str(d / "pic.png"),
        "PAT": str(d / "made" / "pattern.json"),
        "K": str(d / "made" / "program.k"),
    }


@pytest.fixture
def files(made, tmp_path, capsys):
    capsys.readouterr()
    return {**made, "T": tmp_path}


def _all_params():
    ctx = click.Context(cli)
    for name in COMMANDS:
        cmd = cli.get_command(ctx, name)
        subs = cmd.commands.values() if isinstance(cmd, click.Group) else [cmd]
        for sub in subs:
            for p in sub.params:
                yield f"{name} {sub.name} {p.name}", p


def test_every_numeric_option_has_a_checked_type():
    unchecked = []
    for where, p in _all_params():
        if isinstance(p.type, click.types.FloatParamType) and not isinstance(p.type, FiniteFloat):
            unchecked.append(where)
        if isinstance(p.type, click.types.IntParamType) and (
            not isinstance(p.type, click.IntRange) or p.type.min is None
        ):
            unchecked.append(where)
    assert unchecked == []


BAD_NUMBERS = [
    "single PIC --width-cm nan -o OUT",
    "single PIC --width-cm inf -o OUT",
    "single PIC --width-cm -3 -o OUT",
    "single PIC --width-cm 5 --gauge nan -o OUT",
    "single PIC --width -4 -o OUT",
    "demo --width -1 -o OUT",
    "knit PAT --seconds-per-needle nan -o OUT/p.k",
    "knit PAT --seconds-per-turn inf -o OUT/p.k",
    "knit PAT --gauge -7 -o OUT/p.k",
    "knit PAT --catch-every 0 -o OUT/p.k",
    "knit PAT --float-limit -1 -o OUT/p.k",
    "render PAT --angle nan -o OUT",
    "render PAT --angle inf -o OUT",
    "solve PIC --model single --time-limit nan -o OUT",
    "solve PIC --model single --time-limit -5 -o OUT",
    "solve PIC --model single --seed -1 -o OUT",
    "bench --time-limit inf --list",
    "bench --jobs 0 --list",
    "check K --max-racking nan",
    "calibrate fit PIC --flat-height nan -o OUT/x.json",
    "calibrate fit PIC --unit-length -1 -o OUT/x.json",
]


@pytest.mark.parametrize("argv", BAD_NUMBERS)
def test_bad_number_is_one_line_exit_2(argv, files, run_cli):
    out = files["T"] / "out"
    args = [str(out) if a == "OUT" else a.replace("OUT", str(out)) for a in argv.split()]
    args = [files.get(a, a) if a in ("PIC", "PAT", "K") else a for a in args]
    code, _, err = run_cli(args)
    assert_one_line(code, err)
    assert not out.exists()


@pytest.mark.parametrize("command", ["view", "knit", "render"])
def test_deeply_nested_json_is_one_line(command, tmp_path, run_cli):
    deep = tmp_path / "deep.json"
    deep.write_text("[" * 100_000 + "]" * 100_000)
    out = tmp_path / ("out.k" if command == "knit" else "out")
    code, _, err = run_cli([command, str(deep), "-o", str(out)])
    assert_one_line(code, err, "nested too deeply")
    assert not out.exists()


def test_export_wcnf_to_an_unwritable_path(files, run_cli):
    (files["T"] / "afile").write_text("x")
    target = files["T"] / "afile" / "model.wcnf"
    code, _, err = run_cli(
        ["solve", files["PIC"], "--model", "single", "--colors", "2", "--export-wcnf", str(target)],
    )
    assert_one_line(code, err, str(target))


def test_bench_unreachable_dask_scheduler_leaves_nothing(tmp_path, run_cli):
    dask = pytest.importorskip("dask")
    pytest.importorskip("dask.distributed")
    out = tmp_path / "results"
    with dask.config.set({"distributed.comm.timeouts.connect": "1s"}):
        code, _, err = run_cli(
            ["bench", "--instances", "quick", "--methods", "dp", "--executor", "dask",
             "--dask-address", "tcp://127.0.0.1:9", "-o", str(out)],
        )  # fmt: skip
    assert_one_line(code, err, "cannot reach the Dask scheduler")
    assert not out.exists()


@pytest.mark.parametrize("flag", [["--yarns", "black"], ["--colors", "1"]])
def test_solve_with_one_yarn_is_an_error(flag, files, run_cli):
    out = files["T"] / "out"
    code, _, err = run_cli(["solve", files["PIC"], "--model", "single", *flag, "-o", str(out)])
    assert_one_line(code, err, "at least 2 yarns")
    assert not out.exists()


@pytest.mark.parametrize("command", ["view", "render"])
def test_an_outdir_named_like_an_option_is_refused(command, files, run_cli, monkeypatch):
    """``-o --04`` once took "--04" as the folder (a file named like an option, ``--04.png``,
    was committed at the root): a name starting with '-' is refused unless given as a path."""
    monkeypatch.chdir(files["T"])
    code, _, err = run_cli([command, files["PAT"], "-o", "--04"])
    assert_one_line(code, err, "'--04' looks like an option")
    assert not (files["T"] / "--04").exists()
    code, _, err = run_cli([command, files["PAT"], "-o", str(files["T"] / "--04")])
    assert code == 0, err  # a full path is a folder name like any other
    assert (files["T"] / "--04" / "headon.png").is_file()
