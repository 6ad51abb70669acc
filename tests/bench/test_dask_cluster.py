"""The solver benchmark on a real Dask cluster: a scheduler and two workers started with the
ordinary ``dask scheduler`` / ``dask worker`` commands on loopback (daemonic worker processes
under a nanny, each in a folder of its own), against the same table run locally."""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest
from PIL import Image, ImageDraw

import illuknit
from illuknit.bench.instances import load_manifest, select_instances
from illuknit.bench.pictures import picture_instances
from illuknit.bench.solver_table import make_tasks, run_solver_table
from illuknit.bench.wcnf_files import export_wcnf_family

pytest.importorskip("dask.distributed", reason="needs illuknit[dask]")
FAKE = Path(__file__).parents[1] / "solvers" / "fake" / "fake_maxsat.py"


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture
def cluster(tmp_path):
    """``dask scheduler`` and two ``dask worker ADDR`` processes on 127.0.0.1; the workers run
    in folders of their own and import this checkout (PYTHONPATH), nothing else shared."""
    dask = shutil.which("dask")
    if dask is None:
        pytest.skip("the dask command is not installed")
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    env = {**os.environ, "PYTHONPATH": str(Path(illuknit.__file__).parents[1])}
    logs = tmp_path / "logs"
    logs.mkdir()
    procs = [
        subprocess.Popen(
            [dask, "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
            stdout=open(logs / "scheduler.log", "wb"),  # noqa: SIM115 - closed with the process
            stderr=subprocess.STDOUT,
            env=env,
            start_new_session=True,
        )
    ]
    for k in range(2):
        home = tmp_path / f"worker{k}"
        home.mkdir()
        procs.append(
            subprocess.Popen(
                [dask, "worker", address, "--nthreads", "1", "--no-dashboard"],
                cwd=home,
                stdout=open(logs / f"worker{k}.log", "wb"),  # noqa: SIM115
                stderr=subprocess.STDOUT,
                env=env,
                start_new_session=True,
            )
        )
    try:
        from dask.distributed import Client

        deadline = time.monotonic() + 90
        while True:
            try:
                with Client(address, timeout=5) as c:
                    if len(c.scheduler_info()["workers"]) >= 2:
                        break
            except OSError:
                pass
            if time.monotonic() > deadline:
                pytest.fail(
                    "the Dask cluster did not come up: "
                    + "; ".join(p.read_text()[-300:] for p in logs.iterdir())
                )
            time.sleep(0.5)
        yield address
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in procs:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


def test_a_real_cluster_gives_the_local_verified_costs(cluster, tmp_path, monkeypatch):
    quick = select_instances(load_manifest(), "quick")
    # a WCNF file the workers cannot read: a path relative to this process's folder
    client_dir = tmp_path / "client"
    client_dir.mkdir()
    monkeypatch.chdir(client_dir)
    export_wcnf_family(quick[:1], client_dir / "family", models=["logical"])
    (name,) = [p.name for p in (client_dir / "family").glob("*.wcnf")]
    wcnf = f"family/{name}"
    external = f"wcnf:{sys.executable} {FAKE} {{}}"  # a binary started from a daemonic worker
    # a picture pair the workers cannot read either: built here, it travels built (--pair)
    for name, box in (("a.png", (2, 2, 9, 9)), ("b.png", (3, 1, 8, 8))):
        im = Image.new("RGB", (12, 10), "white")
        ImageDraw.Draw(im).ellipse(box, fill="black")
        im.save(client_dir / name)
    pictures = picture_instances([("a.png", "b.png")])

    def table(outdir: str, **kw):
        tasks = make_tasks(quick, ["dp"], time_limit=30)
        tasks += make_tasks([], ["rc2", external], time_limit=30, wcnf_files=[wcnf])
        tasks += make_tasks(pictures, ["cpsat+split"], time_limit=30)
        return run_solver_table(tasks, outdir, **kw)

    local = table("local")
    remote = table("remote", executor="dask", dask_address=cluster)
    assert not (tmp_path / "worker0" / "family").exists()

    def costs(t):
        return {(r["instance"], r["model"], r["solver"]): r["verified_cost"] for r in t.rows}

    assert costs(remote) == costs(local)
    assert len(remote.rows) == len(quick) + 3
    pair = next(r for r in remote.rows if r["instance"] == "a+b")
    assert pair["certificate"] == "reference (dp)" and pair["verified_cost"] is not None
    assert all(r["status"] == "optimal" and not r["flag"] for r in remote.rows), remote.rows
    by_solver = {r["solver"]: r for r in remote.rows if r["model"] == "wcnf"}
    assert by_solver["rc2"]["verified_cost"] == by_solver[external]["verified_cost"]
