"""The benchmark suite: instances x design methods, measured the same way (paper section 8.3).

* :mod:`~illuknit.bench.instances` — the TOML manifest of instances and their drawn targets;
* :mod:`~illuknit.bench.methods` — one adapter per design method (tiles, solvers, gradient, ...);
* :mod:`~illuknit.bench.metrics` — logical error, knitting, peak memory (the picture measures are
  :mod:`illuknit.design.measures`);
* :mod:`~illuknit.bench.cells` — one cell: a method run on an instance, then measured;
* :mod:`~illuknit.bench.runner` — resumable, parallel execution of the cells;
* :mod:`~illuknit.bench.results` — the results columns and folder;
* :mod:`~illuknit.bench.report` — CSV, JSON, Markdown summary, contact sheets, Pareto plot.

Typical use::

    from illuknit.bench import load_manifest, select_instances, run_bench
    insts = select_instances(load_manifest(), "quick")
    run_bench(insts, ["tiles", "dp"], "results/")
"""

from __future__ import annotations

from illuknit.core.lazy import lazy_api

_API: dict[str, str] = {
    "Instance": "illuknit.bench.instances",
    "Manifest": "illuknit.bench.instances",
    "Targets": "illuknit.bench.instances",
    "instance_targets": "illuknit.bench.instances",
    "load_manifest": "illuknit.bench.instances",
    "parse_manifest": "illuknit.bench.instances",
    "select_instances": "illuknit.bench.instances",
    "METHODS": "illuknit.bench.methods",
    "DEFAULT_METHODS": "illuknit.bench.methods",
    "Method": "illuknit.bench.methods",
    "MethodUnavailable": "illuknit.bench.methods",
    "get_method": "illuknit.bench.methods",
    "register_method": "illuknit.bench.methods",
    "run_bench": "illuknit.bench.runner",
    "load_rows": "illuknit.bench.results",
    "write_outputs": "illuknit.bench.report",
}

__all__ = list(_API)


__getattr__, __dir__ = lazy_api(__name__, _API)
