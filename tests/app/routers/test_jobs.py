"""Jobs through the JSON API: errors, privacy, cancelling, stale results (``routers/jobs.py``)."""

from __future__ import annotations

import json
import threading
import time

import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")


from illuknit.app import design
from illuknit.app.jobs import Job, JobRunner


def test_job_errors_are_reported_with_their_field(client, api):
    sid = api.new_session(client)
    r = client.post(f"/api/sessions/{sid}/jobs", json={"kind": "candidates"})
    assert r.status_code == 422 and api.error_of(r)["field"] == "image_a"
    r = client.post(f"/api/sessions/{sid}/jobs", json={"kind": "sweater"})
    assert r.status_code == 422 and api.error_of(r)["field"] == "kind"
    r = client.get(f"/api/sessions/{sid}/jobs/abc")
    assert r.status_code == 404


def test_jobs_are_private_to_their_session(client, double, api):
    other = api.new_session(client)
    job = client.post(f"/api/sessions/{double}/jobs", json={"kind": "candidates"}).json()
    r = client.get(f"/api/sessions/{other}/jobs/{job['id']}")
    assert r.status_code == 404
    assert client.delete(f"/api/sessions/{other}/jobs/{job['id']}").status_code == 404


def test_cancel_a_running_job():
    runner = JobRunner(workers=1)
    seen = []

    def slow(job: Job) -> int:
        for i in range(10_000):
            job.report(i / 10_000, f"step {i}")
            seen.append(i)
            time.sleep(0.001)
        return 1

    job = runner.submit("candidates", slow)
    while not seen:
        time.sleep(0.01)
    assert job.to_json()["status"] == "running"
    assert job.cancel()
    assert job.wait(10)
    assert job.status == "cancelled" and job.result is None
    assert len(seen) < 10_000
    assert not job.cancel()  # already over
    runner.shutdown()


def test_cancel_kills_isolated_work():
    runner = JobRunner(workers=1)
    started = threading.Event()

    def work(job: Job) -> str:
        started.set()
        return job.run_isolated(time.sleep, 120.0)  # a builtin: picklable for the spawned child

    job = runner.submit("knit", work)
    started.wait(10)
    time.sleep(0.2)
    job.cancel()
    assert job.wait(30), "cancelling must stop the worker process, not wait 120 s for it"
    assert job.status == "cancelled"
    ok = runner.submit("knit", lambda j: j.run_isolated(divmod, 7, 2))
    assert ok.wait(60) and ok.status == "done" and ok.result == (3, 1)
    runner.shutdown()


def test_cancel_through_the_api(client, api, pictures):
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.box_picture())
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 18})
    assert api.run_job(client, sid, "candidates")["status"] == "done"
    app = client.app
    gate = threading.Event()

    def blocked(job: Job) -> None:
        while not gate.wait(0.01):
            job.report(0.5, "waiting")

    job = app.state.runner.submit("knit", blocked)
    app.state.store.get(sid).jobs["knit"] = job
    assert client.get(f"/api/sessions/{sid}/jobs/{job.id}").json()["status"] in (
        "queued",
        "running",
    )
    r = client.delete(f"/api/sessions/{sid}/jobs/{job.id}")
    assert r.status_code == 200 and r.json()["status"] == "cancelled"
    gate.set()


def test_a_new_upload_discards_a_stale_job_result(client, api, pictures):
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.box_picture())
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 18})
    r = client.post(f"/api/sessions/{sid}/jobs", json={"kind": "candidates"})
    api.upload(client, sid, "a", pictures.box_picture(top=1))  # while (or after) the job runs
    jid = r.json()["id"]
    deadline = time.monotonic() + 30
    while client.get(f"/api/sessions/{sid}/jobs/{jid}").json()["status"] in ("queued", "running"):
        assert time.monotonic() < deadline
        time.sleep(0.05)
    assert client.get(f"/api/sessions/{sid}/candidates").json()["candidates"] == []


def test_design_errors_are_app_errors():
    with pytest.raises(design.AppRequestError) as e:
        design.render_view(None, "A", angle=0)  # type: ignore[arg-type]
    assert e.value.field == "angle"
    assert json.dumps(design.capabilities())
