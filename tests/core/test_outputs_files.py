"""Single-file outputs only ever replace a regular file; every way a write can fail is one line.

Devices are stood in for by nodes made in the test's own folder (``os.mknod`` of the null and
full devices' numbers), never the system's ``/dev/null`` or ``/dev/full``: the code before this
contract replaced whatever stood at the path.
"""

from __future__ import annotations

import errno
import io
import json
import os
import socket
import stat
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from illuknit.core.errors import OutputPathError, PatternFormatError
from illuknit.core.files import atomic_write_bytes, recover_output_dir, staged_dir
from illuknit.core.pattern import LogicalPattern, Yarn, load_pattern, save_pattern

ROOT = Path(__file__).resolve().parents[2]


def _mknod(path: Path, minor: int) -> bool:
    """A character device with the numbers of /dev/null (minor 3) or /dev/full (7) at ``path``."""
    try:
        os.mknod(path, 0o666 | stat.S_IFCHR, os.makedev(1, minor))
    except (PermissionError, AttributeError, OSError):
        return False
    return True


def _socket(path: Path) -> socket.socket:
    s = socket.socket(socket.AF_UNIX)
    s.bind(str(path))
    return s


def special(kind: str, path: Path) -> object:
    """Make a non-regular entry of ``kind`` at ``path``; something to keep alive (or None)."""
    if kind == "device":
        if not _mknod(path, 3):
            pytest.skip("cannot make a device node here (needs root)")
        return None
    if kind == "fifo":
        os.mkfifo(path)
        return None
    if kind == "socket":
        return _socket(path)
    path.mkdir()
    (path / "inside.txt").write_text("mine")
    return None


def fingerprint(path: Path) -> tuple[int, int, int]:
    st = os.lstat(path)
    return (stat.S_IFMT(st.st_mode), st.st_ino, st.st_rdev)


KINDS = ["device", "fifo", "socket", "folder"]


@pytest.mark.parametrize("kind", KINDS)
def test_atomic_write_refuses_what_is_not_a_regular_file(tmp_path, kind):
    target = tmp_path / "out.k"
    keep = special(kind, target)
    before = fingerprint(target)
    with pytest.raises(OutputPathError, match="not a regular file"):
        atomic_write_bytes(target, b"knitout")
    assert fingerprint(target) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.k"]  # no temporary file left
    del keep


@pytest.mark.parametrize("kind", KINDS)
def test_a_link_to_what_is_not_a_regular_file_is_refused_too(tmp_path, kind):
    target = tmp_path / "thing"
    keep = special(kind, target)
    link = tmp_path / "out.k"
    link.symlink_to(target)
    before = fingerprint(target)
    with pytest.raises(OutputPathError, match="a link to"):
        atomic_write_bytes(link, b"knitout")
    assert link.is_symlink() and fingerprint(target) == before
    del keep


def test_a_link_is_written_through_to_its_target(tmp_path):
    store = tmp_path / "store"
    store.mkdir()
    target = store / "piece.k"
    target.write_text("old")
    link = tmp_path / "piece.k"
    link.symlink_to(Path("store") / "piece.k")  # relative, as people make them
    chain = tmp_path / "latest.k"
    chain.symlink_to(link)
    atomic_write_bytes(chain, b"new")
    assert chain.is_symlink() and link.is_symlink()
    assert target.read_text() == "new"
    assert sorted(p.name for p in store.iterdir()) == ["piece.k"]
    # A dangling link creates its target.
    dangling = tmp_path / "next.k"
    dangling.symlink_to(store / "next.k")
    atomic_write_bytes(dangling, b"made")
    assert dangling.is_symlink() and (store / "next.k").read_text() == "made"


def test_a_link_loop_is_one_clear_error(tmp_path):
    (tmp_path / "a").symlink_to(tmp_path / "b")
    (tmp_path / "b").symlink_to(tmp_path / "a")
    with pytest.raises(OutputPathError, match="link loop"):
        atomic_write_bytes(tmp_path / "a", b"x")
    with pytest.raises(OutputPathError, match="link loop"):
        recover_output_dir(tmp_path / "a")
    with pytest.raises(OutputPathError, match="link loop"), staged_dir(tmp_path / "a" / "sub"):
        pass


def test_a_replaced_file_keeps_its_permissions(tmp_path):
    target = tmp_path / "private.json"
    target.write_text("old")
    target.chmod(0o600)
    atomic_write_bytes(target, b"new")
    assert stat.S_IMODE(target.stat().st_mode) == 0o600 and target.read_text() == "new"


def test_a_full_disk_keeps_the_old_file_and_says_so(tmp_path, monkeypatch):
    target = tmp_path / "piece.k"
    target.write_text("old")
    real_fdopen = os.fdopen

    class Full(io.RawIOBase):
        def __init__(self, fd):
            self.f = real_fdopen(fd, "wb")

        def writable(self):
            return True

        def write(self, b):
            raise OSError(errno.ENOSPC, "No space left on device")

        def close(self):
            self.f.close()
            super().close()

    monkeypatch.setattr(os, "fdopen", lambda fd, mode="r", *a, **k: Full(fd))
    with pytest.raises(OutputPathError, match=r"No space left on device; .*kept as it was"):
        atomic_write_bytes(target, b"new")
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["piece.k"]


def test_a_full_disk_inside_a_folder_write_is_one_error_and_leaves_the_folder(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "pattern.json").write_text("old")
    with pytest.raises(OutputPathError, match="No space left on device"), staged_dir(out) as tmp:
        (tmp / "pattern.json").write_text("new")
        raise OSError(errno.ENOSPC, "No space left on device")  # as PIL's save would
    assert sorted(p.name for p in out.iterdir()) == ["pattern.json"]
    assert (out / "pattern.json").read_text() == "old"


def test_a_live_runs_staging_folder_is_not_taken_for_a_leftover(tmp_path):
    out = tmp_path / "out"
    with staged_dir(out) as first:
        (first / "a.txt").write_text("a")
        with staged_dir(out) as second:  # a second run into the same folder meanwhile
            (second / "b.txt").write_text("b")
        assert first.is_dir() and (first / "a.txt").exists()
    assert sorted(p.name for p in out.iterdir()) == ["a.txt", "b.txt"]


def test_leftovers_of_an_older_illuknit_are_cleaned_and_moved_back(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "pattern.json").write_text("new")
    # An old commit was killed after moving the user's earlier candidate_1/ aside.
    aside = out / ".illuknit-abc123.replaced"
    (aside / "candidate_1").mkdir(parents=True)
    (aside / "candidate_1" / "pattern.json").write_text("earlier")
    (aside / "pattern.json").write_text("superseded")
    partial = out / ".illuknit-def456.partial"
    partial.mkdir()
    (partial / "chart.png").write_bytes(b"half")
    said = recover_output_dir(out)
    assert said and "put back 1" in said and "removed the unfinished files" in said
    assert sorted(p.name for p in out.iterdir()) == ["candidate_1", "pattern.json"]
    assert (out / "candidate_1" / "pattern.json").read_text() == "earlier"
    assert recover_output_dir(out) is None  # once


# -- the command line ----------------------------------------------------------------------------


@pytest.fixture
def pattern_file(tmp_path) -> Path:
    rng = np.random.default_rng(0)
    p = LogicalPattern(
        rng.integers(0, 2, (6, 8)),
        rng.random((6, 8)) < 0.5,
        (Yarn("black", (27, 27, 27)), Yarn("linen", (244, 240, 232))),
    )
    path = tmp_path / "pattern.json"
    save_pattern(p, path)
    return path


def one_error_line(r) -> str:
    lines = r.err.strip().splitlines()
    assert r.code == 2 and len(lines) == 1 and lines[0].startswith("illuknit: error:"), r
    assert "Traceback" not in r.err
    return lines[0]


@pytest.mark.parametrize("kind", KINDS)
def test_knit_and_export_wcnf_refuse_devices_pipes_sockets_folders(
    tmp_path, kind, pattern_file, picture, run_cli
):
    target = tmp_path / "out.k"
    keep = special(kind, target)
    before = fingerprint(target)
    line = one_error_line(run_cli(["knit", pattern_file, "-o", target]))
    assert "not a regular file" in line or "directory" in line
    assert fingerprint(target) == before
    r = run_cli(["solve", picture, "--model", "single", "--export-wcnf", target])
    one_error_line(r)
    assert fingerprint(target) == before
    del keep


def test_knit_to_standard_output(pattern_file, run_cli, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    r = run_cli(["knit", pattern_file, "-o", "-"])
    assert r.code == 0, r.err
    assert r.out.startswith(";!knitout-2") and "wrote standard output" in r.err
    assert not (tmp_path / "-").exists()
    r = run_cli(["knit", pattern_file, "-o", "-", "--json"])
    assert r.out.startswith(";!knitout-2") and json.loads(r.err)["output"] == "standard output"


def test_export_wcnf_to_standard_output(picture, run_cli, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    r = run_cli(["solve", picture, "--model", "single", "--export-wcnf", "-"])
    assert r.code == 0, r.err
    assert "p wcnf" in r.out.splitlines()[0] or r.out.startswith("c")
    assert "wrote standard output" in r.err and not (tmp_path / "-").exists()
    line = one_error_line(
        run_cli(["solve", picture, "--model", "single", "--export-wcnf", "-", "-o", "o"])
    )
    assert "standard output" in line


def test_huge_width_cm_is_one_line(picture, run_cli, tmp_path):
    line = one_error_line(run_cli(["single", picture, "--width-cm", "1e308", "-o", tmp_path / "o"]))
    assert "--width-cm" in line  # refused where it is parsed (cli/options.py CENTIMETRES)
    assert not (tmp_path / "o").exists()


def test_a_link_loop_as_output_is_one_line(pattern_file, run_cli, tmp_path):
    (tmp_path / "a").symlink_to(tmp_path / "b")
    (tmp_path / "b").symlink_to(tmp_path / "a")
    assert "link loop" in one_error_line(run_cli(["view", pattern_file, "-o", tmp_path / "a"]))
    assert "link loop" in one_error_line(run_cli(["knit", pattern_file, "-o", tmp_path / "a"]))


@pytest.mark.parametrize(
    ("key", "raw"), [("cols", "-1"), ("rows", "Infinity"), ("rows", "0"), ("cols", "1e400")]
)
def test_impossible_sizes_in_a_pattern_file(pattern_file, run_cli, tmp_path, key, raw):
    doc = json.loads(pattern_file.read_text())
    text = json.dumps(dict(doc, **{key: 12345})).replace("12345", raw)
    bad = tmp_path / "bad.json"
    bad.write_text(text)
    with pytest.raises(PatternFormatError, match=key):
        load_pattern(bad)
    assert key in one_error_line(run_cli(["view", bad, "-o", tmp_path / "v"]))
    assert key in one_error_line(run_cli(["knit", bad, "-o", tmp_path / "k.k"]))
    assert not (tmp_path / "v").exists() and not (tmp_path / "k.k").exists()


def _illuknit(args, **kw) -> subprocess.CompletedProcess[str]:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run(
        [sys.executable, "-m", "illuknit", *map(str, args)],
        env=env,
        stderr=subprocess.PIPE,
        text=True,
        timeout=120,
        **kw,
    )


def _err_line(r: subprocess.CompletedProcess[str]) -> str:
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in r.stderr, r.stderr
    return lines[0]


def test_a_full_standard_output_is_one_line(tmp_path, pattern_file, picture):
    full = tmp_path / "full"
    if not _mknod(full, 7):
        pytest.skip("cannot make a device node here (needs root)")
    with open(full, "w") as out:
        r = _illuknit(["tiles"], stdout=out)
    assert r.returncode == 2 and "standard output" in _err_line(r)
    with open(full, "w") as out:
        r = _illuknit(["view", pattern_file, "-o", tmp_path / "v"], stdout=out)
    # The files were committed before the summary was printed: exit 3, and the line says so.
    assert r.returncode == 3 and "written all the same" in _err_line(r)
    assert (tmp_path / "v" / "pattern.json").exists()
    with open(full, "w") as out:
        r = _illuknit(["single", picture, "-o", tmp_path / "s"], stdout=out)
    assert r.returncode == 3 and "written all the same" in _err_line(r)
    assert (tmp_path / "s" / "pattern.json").exists()
    # With --knitout the program's summary is printed while the folder is still being written:
    # the failure comes first, so nothing is committed and it is exit code 2.
    with open(full, "w") as out:
        r = _illuknit(["single", picture, "--knitout", "-o", tmp_path / "k"], stdout=out)
    assert r.returncode == 2 and "standard output" in _err_line(r)
    assert not (tmp_path / "k").exists()
    assert stat.S_ISCHR(os.stat(full).st_mode)


def test_a_broken_pipe_is_one_line(tmp_path, pattern_file):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    read, write = os.pipe()
    os.close(read)  # nobody reads: the first write fails with EPIPE
    try:
        r = subprocess.run(
            [sys.executable, "-m", "illuknit", "tiles"],
            env=env,
            stdout=write,
            stderr=subprocess.PIPE,
            text=True,
            timeout=120,
        )
    finally:
        os.close(write)
    assert r.returncode == 2 and "standard output" in _err_line(r)


def _can_mount() -> bool:
    if sys.platform != "linux":
        return False
    probe = subprocess.run(
        ["unshare", "-m", "sh", "-c", "d=$(mktemp -d) && mount -t tmpfs none $d && umount $d"],
        capture_output=True,
    )
    return probe.returncode == 0


@pytest.mark.skipif(not _can_mount(), reason="needs `unshare -m` and mount privileges")
def test_a_really_full_disk_is_one_line_and_keeps_the_old_files(tmp_path, pattern_file, picture):
    vol = tmp_path / "vol"
    vol.mkdir()
    cli = f"PYTHONPATH={ROOT} {sys.executable} -m illuknit"
    script = (
        f"mount -t tmpfs -o size=12k none {vol} && echo old > {vol}/piece.k && "
        f"mkdir {vol}/out && echo old > {vol}/out/pattern.json && "
        f"{cli} knit {pattern_file} -o {vol}/piece.k; echo rc=$?; "
        f"{cli} single {picture} --knitout -o {vol}/out >/dev/null; echo rc=$?; "
        f"cat {vol}/piece.k {vol}/out/pattern.json; ls -A {vol} {vol}/out"
    )
    r = subprocess.run(
        ["unshare", "-m", "--propagation", "private", "sh", "-c", script],
        capture_output=True,
        text=True,
        timeout=180,
    )
    out = r.stdout.split()
    assert out.count("rc=2") == 2, r
    errs = r.stderr.strip().splitlines()
    assert len(errs) == 2 and all("No space left on device" in e for e in errs), r.stderr
    assert "Traceback" not in r.stderr
    assert out.count("old") == 2  # both old files kept
    listing = out[out.index("old") + 2 :]
    assert not [n for n in listing if n.startswith(".")], listing  # no temporary files left


def test_a_closed_standard_output_is_one_line(tmp_path, pattern_file):
    def close_stdout() -> None:
        os.close(1)

    env = dict(os.environ, PYTHONPATH=str(ROOT))
    runs = {
        "tiles": ["tiles"],
        "view": ["view", pattern_file, "-o", tmp_path / "v"],
        "knit": ["knit", pattern_file, "-o", "-"],
    }
    codes = {}
    for name, args in runs.items():
        r = subprocess.run(
            [sys.executable, "-m", "illuknit", *map(str, args)],
            env=env,
            stderr=subprocess.PIPE,
            text=True,
            timeout=120,
            preexec_fn=close_stdout,
        )
        assert "standard output" in _err_line(r), r.stderr
        codes[name] = r.returncode
    # Nothing was printed or written for tiles and knit -o -; view's files were committed.
    assert codes == {"tiles": 2, "view": 3, "knit": 2}
    assert (tmp_path / "v" / "pattern.json").exists()


def test_calibrate_fit_to_standard_output(tmp_path, run_cli):
    csv = tmp_path / "m.csv"
    csv.write_text("flat_rows,bump_rows,angle_deg,note\n1,1,40.0,\n2,1,22.8,\n3,1,15.6,\n")
    r = run_cli(["calibrate", "fit", csv, "-o", "-"])
    assert r.code == 0, r.err
    assert json.loads(r.out)["bump_height"] > 0 and "fitted bump height" in r.err
