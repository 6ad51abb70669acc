"""Machine files: knitout translated into what a knitting machine reads.

``dat``: Shima Seiki KnitPaint ``.dat`` (:func:`illuknit.formats.dat.knitout_to_dat`, read back
with :func:`illuknit.formats.dat.read_dat`); the carriage passes behind it, which the schedulers
count with, are :func:`illuknit.formats.swg_passes.machine_passes`.

``kc``: Kniterate k-code (``.kc``), via :func:`illuknit.formats.kc.knitout_to_kc`.

Submodules are imported on use, so ``import illuknit`` stays light.
"""

from __future__ import annotations

from illuknit.formats.swg_passes import MachinePass, PassKind, machine_passes

__all__ = ["MachinePass", "PassKind", "machine_passes"]
