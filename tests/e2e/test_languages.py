"""The app in each language: the phone's own language is chosen, the switch changes it in
place, and no button's or control's words overflow their box or leave the screen at 200 %
text size (the screens of a search a phone sees most: start, share, photo, the in-app camera,
tapping and its prompts, finding a landmark the friend tapped, the delete sheet), and that
the status over the photo, where its words are cut, opens whole with its "More".

200 % text is emulated as the browsers' text zoom does it (Chrome for Android's text
scaling and Safari's page zoom are page zooms; WCAG 1.4.4's test): the CSS viewport halves
and each CSS px covers twice the device pixels. A root font-size of 200 % would not do: the
stylesheet sizes its text in px, which a root font-size does not scale, so that test would
pass whatever the words' length.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx2
import pytest
from playwright.sync_api import Browser, BrowserContext, Page, Playwright, expect

from testbed.browser import play
from testbed.client import Phone, numbered, start

LANGUAGES = ("en", "es", "fr", "de", "ja")
MODEL = "Pixel 7"
ZOOM = 2

# Every control a finger uses, and what it says: [what, its words, why it fails]. A box too
# small for its words scrolls (scrollWidth > clientWidth, or taller than it shows); a box
# past the window's edge is out of reach. The switch's picker is invisible over its label,
# which is measured instead. The tap screen's instruction is checked too: its words are
# never under the buttons beside them (at 200 % they once were, in German and Japanese).
OVERFLOWING = """() => {
  const found = [];
  const controls = "button, .button, .chip, .tool, .icon-button, .language-switch, input, select";
  for (const element of document.querySelectorAll(controls)) {
    if (element.closest(".language-switch") && element.tagName === "SELECT") continue;
    if (element.classList.contains("visually-hidden")) continue; // a file input behind its label
    const box = element.getBoundingClientRect();
    if (box.width === 0 || getComputedStyle(element).visibility === "hidden") continue;
    const why = [];
    // An empty field is measured with its placeholder in it: the words it shows.
    const empty = element.tagName === "INPUT" && !element.value && element.placeholder;
    if (empty) element.value = element.placeholder;
    // The top bar's status words give way with an ellipsis by design (styles.css): the
    // buttons beside them never do.
    const givesWay = getComputedStyle(element).textOverflow === "ellipsis";
    if (!givesWay && element.scrollWidth > element.clientWidth + 1) why.push("wider than its box");
    if (element.scrollHeight > element.clientHeight + 1) why.push("taller than its box");
    if (box.left < -0.5 || box.right > innerWidth + 0.5) why.push("off the screen");
    if (empty) element.value = "";
    if (why.length) found.push([element.tagName.toLowerCase() + "." + element.className,
                                element.textContent.trim().slice(0, 40), why.join(", ")]);
  }
  // The instruction's words: no word wider than its line, none under a button beside it.
  for (const words of document.querySelectorAll(".prompt-text > *")) {
    const box = words.getBoundingClientRect();
    const why = [];
    if (words.scrollWidth > words.clientWidth + 1) why.push("wider than its box");
    for (const control of words.closest(".prompt").querySelectorAll("button, .button")) {
      const other = control.getBoundingClientRect();
      if (box.left < other.right && other.left < box.right &&
          box.top < other.bottom && other.top < box.bottom) why.push("under a button");
    }
    if (why.length) found.push(["prompt words", words.textContent.trim().slice(0, 40),
                                why.join(", ")]);
  }
  return found;
}"""


def context(
    playwright: Playwright,
    browser: Browser,
    locale: str | None,
    zoom: int = 1,
    model: str = MODEL,
) -> BrowserContext:
    """A phone of ``model`` whose language is ``locale`` (else the browser's), its text
    zoomed ``zoom`` times."""
    device: dict[str, Any] = dict(playwright.devices[model])
    device.pop("default_browser_type", None)
    viewport = device["viewport"]
    device["viewport"] = {"width": viewport["width"] // zoom, "height": viewport["height"] // zoom}
    device["device_scale_factor"] = device["device_scale_factor"] * zoom
    return browser.new_context(**device, locale=locale)


@pytest.fixture
def zoomed(playwright: Playwright, browser: Browser) -> Iterator[Page]:
    """A Japanese phone at 200 % text size (the app starts in its language)."""
    opened = context(playwright, browser, "ja-JP", ZOOM)
    page = opened.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda error: errors.append(str(error)))
    yield page
    opened.close()
    assert errors == []


def speaks(page: Page, language: str) -> None:
    page.wait_for_function("(lang) => document.documentElement.lang === lang", arg=language)


def in_each_language(page: Page) -> Iterator[str]:
    """Switch through every language with the switch, each once its words are laid out."""
    for language in LANGUAGES:
        page.locator("[data-testid=language] select").first.select_option(language)
        speaks(page, language)
        page.wait_for_timeout(50)  # one frame: the words laid out
        yield language


def each_language(page: Page, screen: str) -> list[list[str]]:
    """Switch through every language on this screen; what overflows, by language."""
    return [
        [language, screen, *problem]
        for language in in_each_language(page)
        for problem in page.evaluate(OVERFLOWING)
    ]


def test_the_phones_language_is_chosen_and_kept(
    server: str, playwright: Playwright, browser: Browser, screenshots: Path
) -> None:
    """An Austrian phone reads German, and fetches the German words only (no other language,
    nor the chunks only later screens need: the QR code, Show me, EXIF); the switch's
    Spanish is kept across a reload. The Spanish start and share screens are the README's
    second language."""
    opened = context(playwright, browser, "de-AT")
    page = opened.new_page()
    scripts: list[str] = []
    page.on("request", lambda r: scripts.append(r.url) if r.resource_type == "script" else None)
    try:
        page.goto(f"{server}/")
        speaks(page, "de")
        assert page.get_by_test_id("start").inner_text() == "Suche starten"
        names = sorted(url.rsplit("/", 1)[-1].split("-")[0] for url in scripts)
        assert names == ["de", "index"], scripts
        page.locator("[data-testid=language] select").select_option("es")
        speaks(page, "es")
        page.reload()
        speaks(page, "es")
        assert page.get_by_test_id("start").inner_text() == "Empezar a buscar"
        page.screenshot(path=screenshots / "15-start-es.png")
        page.get_by_test_id("start").tap()
        page.get_by_test_id("qr").wait_for()
        assert page.get_by_test_id("waiting").inner_text().strip() == "Esperando a tu amigo..."
        page.screenshot(path=screenshots / "15b-share-es.png")
    finally:
        opened.close()


# The status over the photo: words cut with no "More" to open them, and once opened, words
# out of reach (below the status's room, which cannot scroll, or below the screen).
STATUS_CUT = """() => {
  const body = document.querySelector(".status-body");
  const words = document.querySelector(".status-words");
  if (!body || !words) return ["no status"];
  const more = document.querySelector("[data-testid=status-more]");
  const open = more?.getAttribute("aria-expanded") === "true";
  const cut = words.offsetHeight > body.clientHeight + 1;
  if (!open) return cut && !more ? ["cut, and nothing opens it"] : [];
  const why = [];
  const style = getComputedStyle(body);
  const scrolls = ["auto", "scroll"].includes(style.overflowY) && style.pointerEvents !== "none";
  if (cut && !scrolls) why.push("opened, still cut");
  body.scrollTop = body.scrollHeight;
  const last = words.lastElementChild.getBoundingClientRect();
  if (last.bottom > body.getBoundingClientRect().bottom + 1) why.push("last words out of reach");
  if (body.getBoundingClientRect().bottom > innerHeight + 0.5) why.push("below the screen");
  body.scrollTop = 0;
  return why;
}"""


def each_status(page: Page, screen: str, shots: Path) -> tuple[list[list[str]], list[str]]:
    """In every language: what of the status over the photo cannot be read, closed and
    opened with its "More"; and the languages in which it had to be opened (English's
    two looks in ``shots``)."""
    found: list[list[str]] = []
    opened: list[str] = []
    more = page.get_by_test_id("status-more")
    for language in in_each_language(page):
        found += [[language, screen, "status", why] for why in page.evaluate(STATUS_CUT)]
        if more.count():
            opened.append(language)
            if language == "en":
                page.screenshot(path=shots / "status-200-percent-closed.png")
            more.tap()
            expect(more).to_have_attribute("aria-expanded", "true")
            if language == "en":
                page.screenshot(path=shots / "status-200-percent-open.png")
            found += [[language, screen, "status", why] for why in page.evaluate(STATUS_CUT)]
            found += [[language, screen, *problem] for problem in page.evaluate(OVERFLOWING)]
            more.tap()
            expect(more).to_have_attribute("aria-expanded", "false")
    return found, opened


def test_no_words_overflow_at_200_percent(
    server: str, api: httpx2.Client, zoomed: Page, screenshots: Path
) -> None:
    page = zoomed
    found: list[list[str]] = []
    page.goto(f"{server}/")
    speaks(page, "ja")  # the phone's language, unasked
    found += each_language(page, "start")

    page.get_by_test_id("start").tap()
    shown = page.get_by_test_id("code")
    shown.wait_for()
    found += each_language(page, "share")

    # The friend joins (over the API): the starter's photo step, then tapping on its photo.
    code = "".join(ch for ch in shown.inner_text() if ch.isdigit())
    joined = api.post("/api/sessions/join", json={"code": code}).raise_for_status().json()
    friend = Phone(api, joined["session_id"], joined["token"], "joiner")
    page.get_by_test_id("open-camera").wait_for()
    found += each_language(page, "photo")
    page.get_by_test_id("open-camera").tap()  # the in-app camera, on Chromium's fake camera
    page.get_by_test_id("camera-close").wait_for()
    found += each_language(page, "camera")
    page.get_by_test_id("camera-close").tap()

    page.get_by_test_id("photo-input").set_input_files(play.TEMPLE / "templeSR0006.png")
    page.get_by_test_id("photo-view").wait_for()
    found += each_language(page, "tap your friend")
    # The status's lens note ("Your photo names no lens...") needs more than its room here.
    expect(page.get_by_test_id("lens-note")).to_be_attached()
    cut, opened = each_status(page, "tap your friend", screenshots)
    found += cut
    assert opened, "the lens note fits at 200 %: this check no longer tries the status's More"
    page.get_by_test_id("mark-line").tap()
    found += each_language(page, "line")
    page.get_by_test_id("mark-landmark").tap()
    found += each_language(page, "landmarks")

    # The friend's photo and two landmarks on it: this phone is asked to find #1.
    friend.uploaded(play.TEMPLE / "templeSR0003.png")
    friend.tapped(landmarks=numbered([(200.0, 150.0), (420.0, 300.0)]))
    page.get_by_test_id("find-prompt").wait_for()
    found += each_language(page, "find")

    page.get_by_test_id("delete-session").tap()
    page.get_by_test_id("confirm-delete").wait_for()
    found += each_language(page, "delete")
    assert found == [], "\n".join(" | ".join(row) for row in found)


# The top bar's words that are cut (an ellipsis: text wider than its box).
CUT = """() => [...document.querySelectorAll(".top-bar .peer-words, .top-bar .save-state")]
  .filter((element) => element.scrollWidth > element.clientWidth + 1)
  .map((element) => element.textContent)"""


def test_the_top_bar_says_friend_online_in_full(
    server: str, api: httpx2.Client, playwright: Playwright, browser: Browser
) -> None:
    """On an iPhone 13 (390 px), with a photo, the friend online and the taps saved, the
    top bar says so in full in every language: its words give way only when more must fit
    (reconnecting, not saved: test_layout.py)."""
    starter, code = start(api)
    events = starter.listen()  # the friend is online
    opened = context(playwright, browser, None, model="iPhone 13")
    try:
        page = opened.new_page()
        page.goto(f"{server}/join/{code}")
        page.get_by_test_id("photo-input").set_input_files(play.TEMPLE / "templeSR0006.png")
        expect(page.get_by_test_id("save-state")).to_have_attribute("data-state", "saved")
        expect(page.get_by_test_id("peer-online")).to_have_attribute("data-online", "true")
        cut = [
            [language, words] for language in in_each_language(page) for words in page.evaluate(CUT)
        ]
        assert cut == []
    finally:
        opened.close()
        starter.ok("DELETE", expect=204)  # which ends the friend's stream
        assert events.ended.wait(10)
