"""The page's "for" control in headless Chromium, at a desk (1440 px) and on a phone (390 px):
made for hand knitting, the cards show the hand knitter's figures, nothing is cut off, and the
console stays clean (the page runs under its Content-Security-Policy)."""

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
def test_made_for_hands_shows_the_hand_figures(browser, base_url, tmp_path, width):  # noqa: F811
    context, page, problems = watched_page(browser, width)
    page.goto(base_url)
    page.wait_for_selector("body[data-ready='1']")
    # the menu is the declared option's words
    words = page.locator("#made_for option").evaluate_all("os => os.map((o) => o.value)")
    assert words == ["machine", "hands"]
    sync_api.expect(page.locator("#made_for")).to_have_value("machine")
    page.locator("#width_units").fill("24")
    upload_up_on(page, tmp_path)
    page.locator("#made_for").scroll_into_view_if_needed()
    page.select_option("#made_for", "hands")
    hand = page.locator(".cand .hand").first
    sync_api.expect(hand).to_contain_text("rows knittable", timeout=120_000)
    sync_api.expect(hand).to_contain_text("longest float")
    sync_api.expect(page.locator(".cand .measures").first).to_be_visible(timeout=120_000)
    assert page.evaluate("document.documentElement.scrollWidth") <= width
    assert page.evaluate(OFF_SCREEN) == []
    box = page.locator("#made_for").bounding_box()
    assert box and box["x"] >= 0 and box["x"] + box["width"] <= width
    page.screenshot(path=str(tmp_path / f"made-for-{width}.png"), full_page=False)
    # back to the machine: no hand figures
    page.select_option("#made_for", "machine")
    sync_api.expect(page.locator(".cand .hand")).to_have_count(0, timeout=120_000)
    assert problems == []
    context.close()
