"""Whether each side reads, on the page, in headless Chromium at a desk (1440 px) and on a phone
(390 px): the cards say the reader's verdict weaker side first, the widths card lists each
width tried and *Use this width* sets it; nothing is cut off and the console stays clean (the
page runs under its Content-Security-Policy). Needs tesseract (the ``reader`` fixture)."""

from __future__ import annotations

import pytest

from tests.app.test_browser import (  # noqa: F401  (module fixtures)
    OFF_SCREEN,
    base_url,
    browser,
    served,
    sync_api,
    upload_up_on,
    watched_page,
)


@pytest.mark.parametrize("width", [1440, 390])
def test_cards_say_which_side_reads_and_a_width_that_reads_is_applied(
    browser,  # noqa: F811
    base_url,  # noqa: F811
    tmp_path,
    width,
    reader,
):
    context, page, problems = watched_page(browser, width, timeout=120_000)
    page.goto(base_url)
    page.wait_for_selector("body[data-ready='1']")
    page.locator("#width_units").fill("24")
    upload_up_on(page, tmp_path)
    # every card: both sides' verdicts, the weaker (a side that does not read) first
    slow = 120_000  # a search and its reading, on a shared machine
    sync_api.expect(page.locator(".cand .reads").first).to_be_visible(timeout=slow)
    for card in page.locator(".cand .reads").all():
        sides = card.locator(".side")
        sync_api.expect(sides).to_have_count(2)
        classes = sides.evaluate_all("ss => ss.map((s) => s.className)")
        texts = sides.all_inner_texts()
        assert all(("side A" in t) != ("side B" in t) for t in texts), texts
        reads = [" ok" in c for c in classes]
        assert reads == sorted(reads), (classes, texts)  # not read (False) before read
        for c, t in zip(classes, texts, strict=True):
            assert t.startswith("✓") if " ok" in c else t.startswith("✗ side"), t
    # how wide must it be: two small widths, started as the button does
    assert page.locator("#widths-card").is_visible()
    page.evaluate("startJob('widths', { widths: [12, 24] }).then(() => loadWidths())")
    rows = page.locator("#widths tbody tr")
    sync_api.expect(rows.first).to_be_visible(timeout=slow)
    tried = rows.evaluate_all("rs => rs.map((r) => Number(r.dataset.width))")
    assert tried in ([12], [12, 24]), tried
    sync_api.expect(page.locator(".widths-answer")).to_contain_text("Both sides read")
    assert page.evaluate("document.documentElement.scrollWidth") <= width
    assert page.evaluate(OFF_SCREEN) == []
    # a width it tried is applied: the width control says so and the row is the current one
    page.locator("#widths tbody tr[data-width='12'] button").click()
    sync_api.expect(page.locator("#width_units")).to_have_value("12", timeout=slow)
    sync_api.expect(page.locator("#widths tbody tr[data-width='12'] td").last).to_have_text(
        "current width", timeout=slow
    )
    sync_api.expect(page.locator(".cand .reads").first).to_be_visible(timeout=slow)
    page.screenshot(path=str(tmp_path / f"reading-{width}.png"), full_page=True)
    assert problems == []
    context.close()
