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
