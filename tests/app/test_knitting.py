"""The machine in the app: the selector's presets bound the width, knitout is made for the chosen
machine, and the export panel has its .dat with the carrier-to-yarn table and needle range."""

from __future__ import annotations

import io

import numpy as np
import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")

from fastapi.testclient import TestClient
from PIL import Image

from illuknit.app import create_app
from illuknit.app.server import AppConfig
from illuknit.core.machine import MACHINES
from illuknit.formats.dat import knitout_to_dat, read_dat


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(AppConfig(isolate_knit=False))) as c:
        yield c


@pytest.fixture()
def sid(client):
    return client.post("/api/sessions").json()["id"]


def picture() -> bytes:
    rgb = np.full((24, 36, 3), 240, np.uint8)
    rgb[6:18, 8:26] = 20
    buf = io.BytesIO()
    Image.fromarray(rgb).save(buf, format="PNG")
    return buf.getvalue()


def test_info_lists_the_machine_presets(client):
    machines = {m["name"]: m for m in client.get("/api/info").json()["machines"]}
    assert set(machines) == set(MACHINES)
    swg = machines["swg091n2"]
    assert swg["needles"] == 252 and swg["max_units"] == MACHINES["swg091n2"].max_units
    assert machines["generic540"]["needles"] == 540 and "dat" in swg["formats"]
    assert client.get("/api/info").json()["defaults"]["machine"] == "generic540"
    # the selector tells every preset apart by its label alone
    labels = [m["label"] for m in machines.values()]
    assert len(set(labels)) == len(labels), labels


def test_width_wider_than_the_bed_is_refused_before_any_work(client, sid):
    assert (
        client.put(f"/api/sessions/{sid}/settings", json={"machine": "SWG091N2"}).status_code == 200
    )
    too_wide = MACHINES["swg091n2"].max_units + 1
    r = client.put(f"/api/sessions/{sid}/settings", json={"width_units": too_wide})
    assert r.status_code == 422
    err = r.json()["error"]
    assert err["field"] == "width_units" and err["code"] == "too_wide"
    assert "252 needles" in err["message"] and "\n" not in err["message"]
    settings = client.get(f"/api/sessions/{sid}").json()["settings"]
    assert settings["machine"] == "swg091n2" and settings["width_units"] == 60
    widest = MACHINES["swg091n2"].max_units
    assert (
        client.put(f"/api/sessions/{sid}/settings", json={"width_units": widest}).status_code == 200
    )


def test_switching_to_a_narrower_bed_is_refused_at_the_machine(client, sid):
    assert client.put(f"/api/sessions/{sid}/settings", json={"width_units": 200}).status_code == 200
    r = client.put(f"/api/sessions/{sid}/settings", json={"machine": "swg091n2"})
    assert r.status_code == 422
    assert r.json()["error"]["field"] == "machine" and r.json()["error"]["code"] == "too_wide"
    assert client.get(f"/api/sessions/{sid}").json()["settings"]["machine"] == "generic540"


def test_physical_width_is_bounded_by_the_bed_too(client, sid):
    client.put(f"/api/sessions/{sid}/settings", json={"machine": "swg091n2"})
    r = client.put(
        f"/api/sessions/{sid}/settings",
        json={"size_mode": "physical", "width_cm": 120, "gauge": 7},
    )
    assert r.status_code == 422 and r.json()["error"]["field"] == "width_cm"


def test_unknown_machine_lists_the_known_ones(client, sid):
    r = client.put(f"/api/sessions/{sid}/settings", json={"machine": "brother-kh930"})
    assert r.status_code == 422
    err = r.json()["error"]
    assert err["field"] == "machine"
    assert err["message"] == (
        f"unknown machine 'brother-kh930'; the machines are {', '.join(MACHINES)}"
    )


@pytest.fixture()
def run(api):
    """``run(client, sid, kind)``: a job run to its end, which must be done."""

    def run_done(client, sid, kind):
        job = api.run_job(client, sid, kind)
        assert job["status"] == "done", job
        return job

    return run_done


def test_knitout_dat_and_the_knitters_facts_for_the_chosen_machine(client, sid, run):
    client.put(f"/api/sessions/{sid}/images/a", files={"file": ("a.png", picture(), "image/png")})
    client.put(
        f"/api/sessions/{sid}/settings",
        json={"mode": "single", "width_units": 18, "machine": "swg091n2"},
    )
    run(client, sid, "candidates")
    run(client, sid, "knit")
    k = client.get(f"/api/sessions/{sid}/knit").json()
    assert k["ready"] and k["machine"] == "swg091n2" and k["formats"] == ["dat"]
    assert k["stats"]["needles"] == 252
    knitout = client.get(f"/api/sessions/{sid}/download/knitout.k").text
    assert ";;Width: 252" in knitout
    # carrier-to-yarn table: every carrier the program brings in holds the named yarn
    table = k["carriers"]
    assert [row["yarn"] for row in table] == ["black", "linen"]
    used = {line.split()[1] for line in knitout.splitlines() if line.startswith("inhook ")}
    assert used == {c for row in table for c in row["carriers"]}
    # needle range: exactly the needles the program knits on
    needles = {
        int(tok[1:])
        for line in knitout.splitlines()
        if line.startswith("knit ")
        for tok in line.split()[2:3]
    }
    assert k["needle_range"] == [min(needles), max(needles)]
    assert k["needle_range"][1] < 252
    assert k["stats"]["time_seconds"] > 0
    dat = client.get(f"/api/sessions/{sid}/download/pattern.dat")
    assert dat.status_code == 200 and "attachment" in dat.headers["content-disposition"]
    assert dat.headers["content-disposition"].endswith('.dat"')
    assert dat.content == knitout_to_dat(knitout)
    assert len(read_dat(dat.content).passes) > 0
    r = client.get(f"/api/sessions/{sid}/download/pattern.kc")
    assert r.status_code == 409 and r.json()["error"]["code"] == "wrong_format"


def test_kniterate_gets_its_kc_with_waste_and_draw_carriers(client, sid, run):
    from illuknit.formats.kc import knitout_to_kc

    client.put(f"/api/sessions/{sid}/images/a", files={"file": ("a.png", picture(), "image/png")})
    client.put(
        f"/api/sessions/{sid}/settings",
        json={"mode": "single", "width_units": 18, "machine": "kniterate"},
    )
    run(client, sid, "candidates")
    run(client, sid, "knit")
    k = client.get(f"/api/sessions/{sid}/knit").json()
    assert k["ready"] and k["machine"] == "kniterate" and k["formats"] == ["kc"]
    spec = MACHINES["kniterate"]
    rows = {row["yarn"]: row["carriers"] for row in k["carriers"]}
    assert rows["draw thread"] == [spec.draw_carrier] and rows["waste yarn"] == [spec.waste_carrier]
    pattern_carriers = {c for y in ("black", "linen") for c in rows[y]}
    assert pattern_carriers.isdisjoint({spec.draw_carrier, spec.waste_carrier})
    knitout = client.get(f"/api/sessions/{sid}/download/knitout.k").text
    r = client.get(f"/api/sessions/{sid}/download/pattern.kc")
    assert r.status_code == 200
    name = r.headers["content-disposition"].split('filename="')[1].rstrip('"')
    assert name.endswith(".kc")
    assert r.text == knitout_to_kc(knitout, name=name)
    # a Shima file for a Kniterate program: refused next to the machine
    r = client.get(f"/api/sessions/{sid}/download/pattern.dat")
    assert r.status_code == 409
    err = r.json()["error"]
    assert err["field"] == "machine" and err["code"] == "wrong_format"
    assert err["message"].startswith("the Kniterate takes .kc, not .dat")


def test_a_long_float_is_refused_for_the_designer_unless_allowed(monkeypatch):
    from illuknit.app.knitting import knit_and_check
    from illuknit.app.schemas import JobIn
    from illuknit.core.errors import AppRequestError
    from illuknit.core.machine import MachineSpec
    from illuknit.core.pattern import pattern_to_json
    from tests.knitting.test_pipeline import _crowded

    # three carriers, a float limit of one needle: the crowded pattern keeps a float long
    monkeypatch.setitem(
        MACHINES, "tight", MachineSpec(name="Tight", float_limit=1, carriers=("1", "2", "3"))
    )
    doc = pattern_to_json(_crowded())
    with pytest.raises(AppRequestError) as info:
        knit_and_check(doc, "tight")
    e = info.value
    assert e.field == "knit" and e.code == "long_floats"
    msg = str(e)
    assert "knitting course" in msg and "pattern row" in msg and "limit is 1" in msg
    assert "allow long floats" in msg and "allow_long_floats" not in msg
    out = knit_and_check(doc, "tight", allow_long_floats=True)
    assert out["stats"]["long_floats"] >= 1 and out["stats"]["longest_float"] > 1
    assert out["stats"]["longest_float_at"]
    assert JobIn(kind="knit", allow_long_floats=True).allow_long_floats
    assert JobIn(kind="knit").allow_long_floats is False
