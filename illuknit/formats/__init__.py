"""Machine files: knitout translated into what a knitting machine reads.

``kc``: Kniterate k-code (``.kc``), via :func:`illuknit.formats.kc.knitout_to_kc`.
"""
