"""``made_for="hands"`` on the constraint models (issue 37 item 1): refused with one line that
says what to use instead, never silently ignored."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from illuknit.cli import main
from illuknit.core.errors import OptionError
from illuknit.design.options import MadeFor
from illuknit.pipeline.solve import HANDS_REFUSAL, check_made_for, solve_design


def test_the_library_refuses_hands_and_says_what_to_use():
    a = np.zeros((8, 8, 3), np.uint8)
    with pytest.raises(OptionError, match="--for hands"):
        solve_design(a, 255 - a, made_for="hands")
    check_made_for("machine")
    check_made_for(MadeFor.MACHINE)
    with pytest.raises(OptionError):
        check_made_for("feet")


def test_the_command_refuses_hands_in_one_line(tmp_path, capsys):
    a = np.zeros((8, 8, 3), np.uint8)
    Image.fromarray(a).save(tmp_path / "a.png")
    Image.fromarray(255 - a).save(tmp_path / "b.png")
    args = ["solve", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "-o", str(tmp_path / "o")]
    with pytest.raises(SystemExit) as exc:
        main([*args, "--for", "hands"])
    assert exc.value.code != 0
    err = capsys.readouterr().err
    assert HANDS_REFUSAL.split(":")[0] in err
    assert not (tmp_path / "o").exists()
