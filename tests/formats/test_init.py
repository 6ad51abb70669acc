"""Which machine takes which file, and the one conversion entry point."""

from __future__ import annotations

import pytest

from illuknit.core.errors import UnknownNameError
from illuknit.core.machine import MACHINES, MachineSpec
from illuknit.formats import check_format, knitout_to_format, machine_formats
from illuknit.formats.dat import knitout_to_dat

K = ";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\nin 3\nknit - f2 3\nknit - f1 3\nout 3\n"


@pytest.mark.parametrize("name", ["generic540", "swg091n2"])
def test_shima_presets_take_dat(name):
    assert machine_formats(MACHINES[name]) == ("knitout", "dat")
    check_format(MACHINES[name], "dat")


def test_the_kniterate_refuses_dat():
    kniterate = MACHINES["kniterate"]
    assert machine_formats(kniterate) == ("knitout", "kc")
    with pytest.raises(UnknownNameError, match="valid: knitout, kc"):
        check_format(kniterate, "dat")
    with pytest.raises(UnknownNameError, match="valid: knitout, dat"):
        check_format(MachineSpec(), "kc")


def test_knitout_to_format():
    assert knitout_to_format(K, "knitout") == K.encode()
    assert knitout_to_format(K, "dat") == knitout_to_dat(K)
    with pytest.raises(UnknownNameError):
        knitout_to_format(K, "gif")
