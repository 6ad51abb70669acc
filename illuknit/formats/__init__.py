"""Machine files: knitout -> what a knitting machine loads.

* :mod:`illuknit.formats.swg_passes` -- the carriage passes of a Shima SWG machine for a program
  (:func:`machine_passes`), the pass model the schedulers count with;
* :mod:`illuknit.formats.dat` -- Shima ``.dat`` writer (:func:`knitout_to_dat`) and reader
  (:func:`read_dat`).
"""

from __future__ import annotations

from illuknit.formats.swg_passes import MachinePass, PassKind, machine_passes

__all__ = ["MachinePass", "PassKind", "machine_passes"]
