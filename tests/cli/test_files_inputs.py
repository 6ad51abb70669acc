"""The command line's files: no output over an input, inputs read with limits (issue 34, 1 and 5).

- Every command compares each output path (``-o``, ``--export-wcnf``, an output folder) with
  every input file before it writes anything: the same path, a symbolic link to it, or the same
  file by device and inode (a hard link) is one error line, exit code 2, the input untouched.
  An input inside the output folder is kept when the command writes no entry of its name, and
  refused (before anything moves) when it does.
- A named pipe, a device, a folder or a socket as an input is refused at once; so are a name
  too long for the system, a name that is not UTF-8 (when missing), and files above their kind's
  size limit.
"""

from __future__ import annotations

import os
import socket
import sys
import threading
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

import click
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from illuknit.cli import cli
from illuknit.cli.options import InputFile, OutputFile, OutputFolder
from illuknit.core.documents import (
    open_input_file,
    read_input_bytes,
    read_text_file,
    shown_path,
)
from illuknit.core.errors import (
    ImageInputError,
    KnitoutParseError,
    OutputOverInputError,
    PatternFormatError,
)
from illuknit.core.files import (
    atomic_write_bytes,
    check_outputs_apart,
    protecting_inputs,
    staged_dir,
)
from illuknit.core.pattern import LogicalPattern, Yarn, save_pattern
from illuknit.pictures.decode import read_picture

posix_only = pytest.mark.skipif(sys.platform == "win32", reason="FIFOs, links and sockets")


class Files(NamedTuple):
    pic: Path
    pic_b: Path
    pattern: Path
    program: Path
    bank: Path
    params: Path
    measurements: Path
    manifest: Path


@pytest.fixture
def files(tmp_path: Path, box_picture: Callable[[tuple[int, int]], Path]) -> Files:
    pic = box_picture((20, 30))
    pic_b = tmp_path / "pic_b.png"
    pic_b.write_bytes(pic.read_bytes())
    rng = np.random.default_rng(0)
    pattern = tmp_path / "p.json"
    save_pattern(
        LogicalPattern(
            rng.integers(0, 2, (6, 8)),
            rng.random((6, 8)) < 0.5,
            (Yarn("black", (27, 27, 27)), Yarn("linen", (244, 240, 232))),
        ),
        pattern,
    )
    program = tmp_path / "prog.k"
    program.write_text(";!knitout-2\n;;Carriers: 1 2 3 4 5 6\n")
    bank = tmp_path / "bank.json"
    bank.write_text("{}")
    params = tmp_path / "params.json"
    params.write_text("{}")
    measurements = tmp_path / "m.csv"
    measurements.write_text("flat_rows,angle_deg\n1,30\n")
    manifest = tmp_path / "manifest.toml"
    manifest.write_text("")
    return Files(pic, pic_b, pattern, program, bank, params, measurements, manifest)


#: Every command: a command line whose output is one of its inputs (None: it reads no file of
#: the user's, or writes none). A new command must be added here (test_every_command_is_listed).
OVER_INPUT: dict[str, Callable[[Files], list[object]] | None] = {
    "bench": lambda f: ["bench", "--manifest", f.manifest, "-o", f.manifest],
    "app": None,  # reads no file; its data folder is its own
    "demo": None,  # reads no file
    "legible": None,  # writes no file
    "single": lambda f: ["single", f.pic, "-o", f.pic],
    "view": lambda f: ["view", f.pattern, "-o", f.pattern],
    "knit": lambda f: ["knit", f.pattern, "-o", f.pattern],
    "check": None,  # writes nothing
    "tiles": lambda f: ["tiles", "--bank", f.bank, "-o", f.bank],
    "double": lambda f: ["double", f.pic, f.pic_b, "-o", f.pic_b],
    "headon": lambda f: ["headon", f.pic, "-o", f.pic],
    "render": lambda f: ["render", f.pattern, "-o", f.pattern],
    "solve": lambda f: ["solve", f.pic, "--model", "single", "--export-wcnf", f.pic],
    "calibrate swatch": lambda f: ["calibrate", "swatch", "--params", f.params, "-o", f.params],
    "calibrate fit": lambda f: ["calibrate", "fit", f.measurements, "-o", f.measurements],
    "calibrate time": lambda f: ["calibrate", "time", f.program, "--minutes", "3", "-o", f.program],
}


def leaf_commands() -> dict[str, click.Command]:
    ctx = click.Context(cli)
    out: dict[str, click.Command] = {}

    def walk(cmd: click.Command, prefix: list[str]) -> None:
        if isinstance(cmd, click.Group):
            for name in cmd.list_commands(ctx):
                sub = cmd.get_command(ctx, name)
                assert sub is not None
                walk(sub, [*prefix, name])
        else:
            out[" ".join(prefix)] = cmd

    walk(cli, [])
    return out


def one_error_line(r) -> str:
    lines = r.err.strip().splitlines()
    assert r.code == 2 and len(lines) == 1 and lines[0].startswith("illuknit: error:"), r
    assert "Traceback" not in r.err
    return lines[0]


def snapshot(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


def test_every_command_is_listed():
    assert set(leaf_commands()) == set(OVER_INPUT)


def test_every_path_parameter_says_whether_it_is_read_or_written():
    """A plain click.Path would escape the comparison of outputs with inputs."""
    for name, cmd in leaf_commands().items():
        for p in cmd.params:
            if isinstance(p.type, click.Path) and name != "app":
                assert isinstance(p.type, (InputFile, OutputFile, OutputFolder)), (name, p.name)


@pytest.mark.parametrize("command", [c for c, argv in OVER_INPUT.items() if argv is not None])
def test_no_command_writes_over_its_input(command, files, run_cli, tmp_path):
    argv = OVER_INPUT[command]
    assert argv is not None
    before = snapshot(tmp_path)
    line = one_error_line(run_cli(argv(files)))
    assert "input file" in line or "is a file" in line, line
    assert snapshot(tmp_path) == before


@posix_only
@pytest.mark.parametrize("link", ["symlink", "hardlink", "dotted"])
def test_an_output_that_reaches_the_input_another_way_is_refused(link, files, run_cli, tmp_path):
    out = tmp_path / "out.k"
    if link == "symlink":
        out.symlink_to(files.pattern.name)
    elif link == "hardlink":
        os.link(files.pattern, out)
    else:
        out = tmp_path / "sub" / ".." / files.pattern.name
        (tmp_path / "sub").mkdir()
    before = files.pattern.read_bytes()
    line = one_error_line(run_cli(["knit", files.pattern, "-o", out]))
    assert "refusing to write" in line and "p.json" in line
    assert files.pattern.read_bytes() == before


def test_issue_cases(files, run_cli, tmp_path, monkeypatch):
    """The three cases of issue 34 (each destroyed the input on main, mostly with exit 0)."""
    monkeypatch.chdir(tmp_path)
    before = snapshot(tmp_path)
    one_error_line(run_cli(["knit", "p.json", "-o", "p.json"]))
    one_error_line(run_cli(["calibrate", "time", "prog.k", "--minutes", "3", "-o", "prog.k"]))
    one_error_line(run_cli(["solve", "pic.png", "--model", "single", "--export-wcnf", "pic.png"]))
    line = one_error_line(
        run_cli(["solve", "pic.png", "--model", "single", "--export-wcnf", "./pic.png", "-o", "o"])
    )
    assert "refusing to write pic.png: it is the input file pic.png" in line
    assert snapshot(tmp_path) == before and not (tmp_path / "o").exists()


def test_a_machine_file_is_an_input(files, run_cli, tmp_path):
    machine = tmp_path / "m.json"
    machine.write_text("{}")
    argv = ["calibrate", "time", files.program, "--minutes", "3", "--machine", machine]
    assert "m.json" in one_error_line(run_cli([*argv, "-o", machine]))
    assert machine.read_text() == "{}"


def test_an_input_in_the_output_folder_is_kept_or_the_run_refused(files, run_cli, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    mine = out / "mine.json"  # a name view does not write: kept, the run goes ahead
    mine.write_bytes(files.pattern.read_bytes())
    r = run_cli(["view", mine, "-o", out])
    assert r.code == 0, r.err
    assert mine.read_bytes() == files.pattern.read_bytes() and (out / "pattern.json").exists()
    (out / "pattern.json").write_bytes(files.pattern.read_bytes())  # the name view writes
    before = snapshot(out)
    line = one_error_line(run_cli(["view", out / "pattern.json", "-o", out]))
    assert "pattern.json" in line and "input file" in line
    assert snapshot(out) == before
    assert not [p for p in os.listdir(out) if p.startswith(".illuknit-")]


def test_library_guards(tmp_path):
    src = tmp_path / "in.json"
    src.write_text("x")
    with pytest.raises(OutputOverInputError, match=r"in\.json"):
        check_outputs_apart([src], folders=[src])
    check_outputs_apart([src], files=[tmp_path / "other.json", "-"], folders=[tmp_path])
    with protecting_inputs([src]):
        with pytest.raises(OutputOverInputError):
            atomic_write_bytes(src, b"y")
        inner = tmp_path / "folder"
        inner.mkdir()
        (inner / "data").mkdir()
        (inner / "data" / "kept.json").write_text("k")
        with (
            protecting_inputs([inner / "data" / "kept.json"]),
            pytest.raises(OutputOverInputError, match="holds the input"),
            staged_dir(inner) as stage,
        ):
            (stage / "data").mkdir()  # would replace the folder holding an input
    assert src.read_text() == "x" and (inner / "data" / "kept.json").read_text() == "k"
    atomic_write_bytes(src, b"z")  # outside the block, a plain write
    assert src.read_text() == "z"


# -- inputs read with limits ----------------------------------------------------------------------

#: Every input-file parameter of every command, and a command line around it.
INPUT_PARAMS: dict[str, Callable[[Files, object], list[object]]] = {
    "single": lambda f, x: ["single", x, "-o", "out"],
    "view": lambda f, x: ["view", x, "-o", "out"],
    "knit": lambda f, x: ["knit", x, "-o", "out.k"],
    "check": lambda f, x: ["check", x],
    "tiles --bank": lambda f, x: ["tiles", "--bank", x, "-o", "out"],
    "double": lambda f, x: ["double", f.pic, x, "-o", "out"],
    "legible": lambda f, x: ["legible", f.pic, x],
    "headon": lambda f, x: ["headon", x, "-o", "out"],
    "render": lambda f, x: ["render", x, "-o", "out"],
    "render --params": lambda f, x: ["render", f.pattern, "--params", x, "-o", "out"],
    "solve": lambda f, x: ["solve", x, "--model", "single", "--export-wcnf", "out.wcnf"],
    "calibrate fit": lambda f, x: ["calibrate", "fit", x, "-o", "out.json"],
    "calibrate time": lambda f, x: ["calibrate", "time", x, "--minutes", "3", "-o", "o.json"],
    "calibrate swatch --params": lambda f, x: ["calibrate", "swatch", "--params", x, "-o", "o"],
    "bench --manifest": lambda f, x: ["bench", "--manifest", x, "--list"],
    "bench --wcnf": lambda f, x: ["bench", "--wcnf", x, "--list"],
    "bench --pair": lambda f, x: ["bench", "--pair", f.pic, x, "--solvers", "rc2", "-o", "out"],
    "double --bank": lambda f, x: ["double", f.pic, f.pic_b, "--bank", x, "-o", "out"],
    "headon --bank": lambda f, x: ["headon", f.pic, "--bank", x, "-o", "out"],
    "calibrate fit --params": lambda f, x: [
        *("calibrate", "fit", f.measurements, "--params", x, "-o", "out.json")
    ],
}


def test_every_input_parameter_is_listed():
    found = set()
    for name, cmd in leaf_commands().items():
        for p in cmd.params:
            if isinstance(p.type, InputFile):
                opt = [o for o in p.opts if o.startswith("--")]
                found.add(f"{name} {opt[0]}" if opt else name)
    assert found == set(INPUT_PARAMS)


def bad_inputs(tmp_path: Path) -> dict[str, object]:
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    folder = tmp_path / "folder.png"
    folder.mkdir()
    return {
        "fifo": fifo,
        "dev-zero": "/dev/zero",
        "folder": folder,
        "long-name": tmp_path / ("a" * 300 + ".png"),
        "not-utf8": os.fsdecode(bytes(tmp_path / "x") + b"\xff\xfe.png"),
        "missing": tmp_path / "missing.png",
    }


@posix_only
@pytest.mark.parametrize("where", sorted(INPUT_PARAMS))
def test_bad_inputs_are_one_line_at_once(where, files, run_cli, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    for kind, bad in bad_inputs(tmp_path).items():
        line = one_error_line(run_cli(INPUT_PARAMS[where](files, bad)))
        assert "file" in line, (kind, line)
        assert len(line) < 400, (kind, line)
    assert not (tmp_path / "out").exists() and not (tmp_path / "out.k").exists()


@posix_only
def test_the_library_refuses_pipes_devices_folders_sockets_and_big_files(tmp_path):
    bad = bad_inputs(tmp_path)
    sock = socket.socket(socket.AF_UNIX)
    sock.bind(str(tmp_path / "sock"))
    try:
        for path in [*bad.values(), tmp_path / "sock"]:
            with pytest.raises(PatternFormatError):
                read_text_file(path, error=PatternFormatError, what="pattern")  # type: ignore[arg-type]
            with pytest.raises(ImageInputError):
                read_picture(path)  # type: ignore[arg-type]
    finally:
        sock.close()
    big = tmp_path / "big.k"
    big.write_bytes(b";" * 2000)
    with pytest.raises(KnitoutParseError, match="above the 1000 bytes limit"):
        read_input_bytes(big, error=KnitoutParseError, what="program", limit=1000)
    assert read_input_bytes(big, error=KnitoutParseError, what="program", limit=2000)


@posix_only
def test_a_fifo_never_blocks(tmp_path):
    """Opening a FIFO for reading waits for a writer; the readers must not (O_NONBLOCK + fstat)."""
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    outcome: list[object] = []

    def read() -> None:
        try:
            open_input_file(fifo, error=PatternFormatError, what="pattern")
        except PatternFormatError as e:
            outcome.append(e)

    t = threading.Thread(target=read, daemon=True)
    t.start()
    t.join(timeout=30)  # generous: a block would never end
    if t.is_alive():  # unblock the reader so the test process can end
        with open(fifo, "wb"):
            pass
    assert outcome and "named pipe" in str(outcome[0])


def test_a_100000_character_yarn_name_is_one_short_line(files, run_cli, tmp_path):
    name = "b" * 100_000
    line = one_error_line(
        run_cli(["single", files.pic, "--yarns", f"#222,{name}=#eee", "-o", tmp_path / "o"])
    )
    assert "100000 characters" in line and len(line) < 300
    line = one_error_line(run_cli(["single", files.pic, "--yarns", name, "-o", tmp_path / "o"]))
    assert "unknown yarn colour" in line and len(line) < 300


@posix_only
def test_names_that_are_not_utf8_are_written_and_read(files, run_cli, tmp_path):
    odd = Path(os.fsdecode(bytes(tmp_path) + b"/\xff\xfe.json"))
    odd.write_bytes(files.pattern.read_bytes())
    out = Path(os.fsdecode(bytes(tmp_path) + b"/\xff.k"))
    r = run_cli(["knit", odd, "-o", out])
    assert r.code == 0 and "Traceback" not in r.err, r
    assert out.read_bytes().startswith(b";!knitout-2")
    r = run_cli(["view", odd, "-o", Path(os.fsdecode(bytes(tmp_path) + b"/o\xff"))])
    assert r.code == 0 and "Traceback" not in r.err, r


@pytest.mark.parametrize(
    "argv",
    [
        lambda f, name: ["knit", f.pattern, "-o", f"{name}.k"],
        lambda f, name: ["view", f.pattern, "-o", name],
        lambda f, name: ["view", f.pattern, "-o", f"{name}/sub"],
        lambda f, name: ["solve", f.pic, "--model", "single", "--export-wcnf", f"{name}.wcnf"],
    ],
)
def test_an_output_name_too_long_is_one_short_line(argv, files, run_cli, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    line = one_error_line(run_cli(argv(files, "a" * 300)))
    assert "too long" in line and len(line) < 400, line


@settings(max_examples=200, deadline=None)
@given(st.binary(min_size=1, max_size=400))
def test_any_file_name_is_shown_on_one_printable_line(raw):
    shown = shown_path(os.fsdecode(raw))
    shown.encode("utf-8")  # prints anywhere: no lone surrogates left
    assert not any(ord(ch) < 0x20 or 0x7F <= ord(ch) < 0xA0 for ch in shown)
    assert len(shown) <= 250


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    st.lists(st.sampled_from([".", "sub/..", "sub/./..", "./sub/.."]), max_size=4), st.booleans()
)
def test_every_spelling_of_the_input_is_refused(tmp_path, detours, other):
    (tmp_path / "sub").mkdir(exist_ok=True)
    src = tmp_path / "in.json"
    src.write_text("x")
    name = "other.json" if other else "in.json"
    spelled = Path(tmp_path, *detours, name)
    if other:
        check_outputs_apart([src], files=[spelled])
    else:
        with pytest.raises(OutputOverInputError):
            check_outputs_apart([src], files=[spelled])
    assert src.read_text() == "x"
