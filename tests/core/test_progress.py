"""The progress bar is silent off a terminal and counts steps on one."""

import io

from rich.console import Console

from illuknit.core.progress import progress


def test_progress_is_silent_when_not_a_terminal(capsys):
    with progress(3, "render") as advance:
        for _ in range(3):
            advance()
    assert capsys.readouterr().err == ""


def test_progress_counts_on_a_terminal(monkeypatch):
    buf = io.StringIO()
    monkeypatch.setattr(
        "rich.console.Console",
        lambda **kw: Console(file=buf, force_terminal=True, width=80),
    )
    with progress(2, "sweep") as advance:
        advance(description="frame 1")
        advance(steps=1)
    assert "sweep" in buf.getvalue()


def test_work_bar_is_silent_when_not_a_terminal(capsys):
    from illuknit.core.progress import work_bar

    with work_bar("double", delay=0) as report:
        report(0.5, "halfway")
    assert capsys.readouterr().err == ""


def test_work_bar_shows_only_work_that_lasts(monkeypatch):
    """A bar appears once the work has run ``delay`` seconds; quicker work prints nothing."""
    import time

    from illuknit.core.progress import work_bar

    buf = io.StringIO()
    monkeypatch.setattr(
        "rich.console.Console",
        lambda **kw: Console(file=buf, force_terminal=True, width=100),
    )
    with work_bar("quick", delay=5) as report:
        report(1.0, "done")
    assert buf.getvalue() == ""
    with work_bar("slow", delay=0.05) as report:
        report(0.25, "finding tile designs")
        time.sleep(0.5)
    assert "slow" in buf.getvalue() and "finding tile designs" in buf.getvalue()


def test_every_slow_command_shows_a_bar_on_a_terminal(monkeypatch, tmp_path):
    """demo, view, knit, check and tiles run 3-13 s: on a terminal each shows a bar (issue 33)."""
    import illuknit.core.progress as progress_module
    from illuknit.cli import main

    buf = io.StringIO()
    monkeypatch.setattr(
        "rich.console.Console",
        lambda **kw: (
            Console(file=buf, force_terminal=True, width=100)
            if kw.get("stderr")
            else Console(file=io.StringIO(), width=100)
        ),
    )
    monkeypatch.setattr(progress_module, "DELAY", 0.0)
    demo = tmp_path / "demo"
    runs = {
        "demo": ["demo", "--width", "12", "-o", str(demo)],
        "view": ["view", str(demo / "pattern.json"), "-o", str(tmp_path / "view")],
        "knit": ["knit", str(demo / "pattern.json"), "-o", str(tmp_path / "p.k")],
        "check": ["check", str(tmp_path / "p.k")],
        "tiles": ["tiles"],
    }
    for label, argv in runs.items():
        buf.truncate(0)
        buf.seek(0)
        main(argv)
        assert label in buf.getvalue(), (label, buf.getvalue()[:300])
