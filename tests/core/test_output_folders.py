"""The output-folder contract (illuknit.core.files): the named folder, resolved; staging inside it;
other files kept; a failure leaves the folder as it was."""

import errno
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from illuknit.core.errors import OutputPathError
from illuknit.core.files import staged_dir


def write(outdir, **files):
    with staged_dir(outdir) as tmp:
        for name, text in files.items():
            (tmp / name).write_text(text)


def tree(root: Path) -> dict[str, str]:
    """Every file under ``root`` (relative path -> content), hidden ones included."""
    return {
        str(p.relative_to(root)): p.read_text() if p.is_file() else "<dir>"
        for p in sorted(root.rglob("*"))
    }


@pytest.fixture
def nest(tmp_path):
    """tmp/parent/{summary.json, here/{keep.txt}} with a same-named entry in the parent."""
    parent = tmp_path / "parent"
    here = parent / "here"
    here.mkdir(parents=True)
    (parent / "summary.json").write_text("parent's own")
    (parent / "candidate_1").mkdir()
    (parent / "candidate_1" / "mine.txt").write_text("user's file")
    (here / "keep.txt").write_text("keep me")
    return parent, here


def test_dot_is_the_current_folder_not_its_parent(nest, monkeypatch):
    parent, here = nest
    before = tree(parent / "candidate_1") | {"s": (parent / "summary.json").read_text()}
    monkeypatch.chdir(here)
    write(".", **{"summary.json": "new"})
    assert (here / "summary.json").read_text() == "new"
    assert (here / "keep.txt").read_text() == "keep me"
    assert tree(parent / "candidate_1") | {"s": (parent / "summary.json").read_text()} == before
    assert sorted(p.name for p in here.iterdir()) == ["keep.txt", "summary.json"]


def test_dotdot_is_the_folder_above(nest, monkeypatch):
    parent, here = nest
    monkeypatch.chdir(here)
    write("..", **{"out.txt": "x"})
    assert (parent / "out.txt").read_text() == "x"
    assert not (parent.parent / "out.txt").exists()
    write(here / "sub" / "..", **{"b.txt": "y"})
    assert (here / "b.txt").read_text() == "y"
    assert not (parent / "b.txt").exists()


def test_symlink_writes_into_its_target(tmp_path):
    real = tmp_path / "store" / "real"
    real.mkdir(parents=True)
    (real / "old.txt").write_text("old")
    link = tmp_path / "link"
    link.symlink_to(real, target_is_directory=True)
    write(link, **{"new.txt": "new"})
    assert link.is_symlink()
    assert sorted(p.name for p in real.iterdir()) == ["new.txt", "old.txt"]
    assert not (real.parent / "link").exists()  # not beside the target under the link's name


def test_same_named_entries_replaced_others_kept(tmp_path):
    out = tmp_path / "out"
    (out / "candidate_1").mkdir(parents=True)
    (out / "candidate_1" / "stale.png").write_text("stale")
    (out / "notes.txt").write_text("mine")
    with staged_dir(out) as tmp:
        (tmp / "candidate_1").mkdir()
        (tmp / "candidate_1" / "pattern.json").write_text("{}")
    assert tree(out) == {
        "candidate_1": "<dir>",
        "candidate_1/pattern.json": "{}",
        "notes.txt": "mine",
    }


def test_existing_file_as_parent_is_one_clear_error(tmp_path):
    (tmp_path / "existing_file").write_text("x")
    with pytest.raises(OutputPathError, match="file in the way"):
        write(tmp_path / "existing_file" / "sub", a="a")
    with pytest.raises(OutputPathError, match="is a file"):
        write(tmp_path / "existing_file", a="a")
    assert tree(tmp_path) == {"existing_file": "x"}


def test_failure_in_block_leaves_folder_as_it_was(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "a.txt").write_text("a")
    before = tree(tmp_path)
    with pytest.raises(RuntimeError), staged_dir(out) as tmp:
        (tmp / "a.txt").write_text("half")
        raise RuntimeError("boom")
    assert tree(tmp_path) == before
    # A folder the call created is removed again.
    with pytest.raises(RuntimeError), staged_dir(tmp_path / "new" / "deeper"):
        raise RuntimeError("boom")
    assert tree(tmp_path) == before


def test_failure_while_moving_in_rolls_back(tmp_path, monkeypatch):
    out = tmp_path / "out"
    (out / "b").mkdir(parents=True)
    (out / "b" / "old.txt").write_text("old b")
    (out / "a.txt").write_text("old a")
    (out / "keep.txt").write_text("keep")
    before = tree(tmp_path)
    real_replace = os.replace
    calls = []

    def flaky(src, dst):
        calls.append(dst)
        if len(calls) == 4:  # after a.txt is swapped and b's old folder moved aside
            raise OSError(errno.EROFS, "Read-only file system")
        return real_replace(src, dst)

    monkeypatch.setattr(os, "replace", flaky)
    with pytest.raises(OutputPathError, match="Read-only file system"), staged_dir(out) as tmp:
        (tmp / "a.txt").write_text("new a")
        (tmp / "b").mkdir()
        (tmp / "b" / "new.txt").write_text("new b")
    assert tree(tmp_path) == before


def test_read_only_folder_is_one_clear_error(tmp_path, monkeypatch):
    # Root ignores permission bits; a read-only file system is what access() reports here.
    out = tmp_path / "ro"
    out.mkdir()
    (out / "x.txt").write_text("x")
    monkeypatch.setattr(os, "access", lambda path, mode: False)
    with pytest.raises(OutputPathError, match="cannot write to output folder"):
        write(out, y="y")
    assert tree(tmp_path) == {"ro": "<dir>", "ro/x.txt": "x"}


def _mount_simulated(monkeypatch, mount: Path) -> None:
    """Make renames across ``mount``'s boundary fail with EXDEV, as for a real mount point."""
    mount = mount.resolve()

    def inside(p) -> bool:
        p = Path(os.path.abspath(p))
        return p == mount or mount in p.parents

    for name in ("replace", "rename"):
        real = getattr(os, name)

        def cross(src, dst, *a, _real=real, **k):
            if inside(src) != inside(dst):
                raise OSError(errno.EXDEV, "Invalid cross-device link")
            return _real(src, dst, *a, **k)

        monkeypatch.setattr(os, name, cross)


def test_mount_point_as_output_folder_simulated(tmp_path, monkeypatch):
    mount = tmp_path / "volume"
    mount.mkdir()
    (mount / "keep.txt").write_text("keep")
    _mount_simulated(monkeypatch, mount)
    with staged_dir(mount) as tmp:
        (tmp / "pattern.json").write_text("{}")
        (tmp / "sub").mkdir()
        (tmp / "sub" / "x.png").write_text("png")
    assert tree(tmp_path) == {
        "volume": "<dir>",
        "volume/keep.txt": "keep",
        "volume/pattern.json": "{}",
        "volume/sub": "<dir>",
        "volume/sub/x.png": "png",
    }


def test_exdev_rename_falls_back_to_copy(tmp_path, monkeypatch):
    out = tmp_path / "out"
    out.mkdir()
    (out / "sub").mkdir()
    (out / "sub" / "old.txt").write_text("old")

    def exdev(src, dst):
        raise OSError(errno.EXDEV, "Invalid cross-device link")

    monkeypatch.setattr(os, "replace", exdev)
    with staged_dir(out) as tmp:
        (tmp / "a.txt").write_text("a")
        (tmp / "sub").mkdir()
        (tmp / "sub" / "new.txt").write_text("new")
    assert tree(out) == {"a.txt": "a", "sub": "<dir>", "sub/new.txt": "new"}


def _can_mount() -> bool:
    if sys.platform != "linux" or shutil.which("unshare") is None:
        return False
    probe = subprocess.run(
        ["unshare", "-m", "sh", "-c", "d=$(mktemp -d) && mount -t tmpfs none $d && umount $d"],
        capture_output=True,
    )
    return probe.returncode == 0


needs_mount = pytest.mark.skipif(
    not _can_mount(), reason="needs `unshare -m` and mount privileges (a private mount namespace)"
)


@pytest.fixture
def picture(box_picture):
    return box_picture((12, 16))


def _in_namespace(script: str) -> subprocess.CompletedProcess[str]:
    # A private mount namespace: the tmpfs vanishes with the process, nothing leaks.
    return subprocess.run(
        ["unshare", "-m", "--propagation", "private", "sh", "-c", script],
        capture_output=True,
        text=True,
        timeout=120,
    )


@needs_mount
def test_cli_into_a_real_mount_point(tmp_path, picture):
    vol = tmp_path / "vol"
    vol.mkdir()
    cli = f"{sys.executable} -m illuknit"
    r = _in_namespace(
        f"mount -t tmpfs none {vol} && echo mine > {vol}/keep.txt && "
        f"{cli} single {picture} -o {vol} >/dev/null && ls -A {vol} && ls -A {tmp_path}"
    )
    assert r.returncode == 0, r.stderr
    listing = r.stdout.split()
    assert "keep.txt" in listing and "pattern.json" in listing
    assert not [n for n in listing if n.endswith(".partial")]


@needs_mount
def test_cli_into_a_read_only_mount(tmp_path, picture):
    vol = tmp_path / "ro"
    vol.mkdir()
    r = _in_namespace(
        f"mount -t tmpfs -o ro none {vol} && {sys.executable} -m illuknit single {picture} -o {vol}/out"
    )
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "read-only file system" in lines[0], r.stderr
