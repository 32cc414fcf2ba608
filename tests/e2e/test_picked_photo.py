"""A phone's own photo, in each engine: 48 MP, turned by its EXIF orientation, as an iPhone
takes it. The phone must send it small and upright (frontend/src/downscale.ts) without ever
making a canvas beyond iOS Safari's 16.7 MP.
"""

from __future__ import annotations

import io
from pathlib import Path

import httpx2
import pytest
from PIL import Image, ImageOps

from testbed.browser import play
from testbed.browser.phone import Phone, expect

pytestmark = pytest.mark.engines("chromium", "webkit")

# The upright photo: 6048 x 8064 (48.8 MP, portrait), four coloured quarters, so a photo
# turned or mirrored the wrong way shows it.
UPRIGHT = (6048, 8064)
QUARTERS = {"top-left": (230, 30, 30), "top-right": (30, 200, 30), "bottom-left": (30, 30, 230)}
REST = (240, 220, 30)  # bottom-right
EXIF_ORIENTATION = 274
ROTATE_90_CW = 6  # "turn the stored pixels a quarter clockwise to show them"
STORED_SIDE = 2560  # the app's STORED_PHOTO_SIDE
CANVAS_CAP = 16_777_216  # iOS Safari's canvas limit, in px

# Before the photo is chosen: record every canvas size the page sets, and what it sends.
SPY = """() => {
  window.canvasAreas = [];
  const proto = HTMLCanvasElement.prototype;
  for (const side of ["width", "height"]) {
    const own = Object.getOwnPropertyDescriptor(proto, side);
    Object.defineProperty(proto, side, { ...own, set(value) {
      own.set.call(this, value);
      window.canvasAreas.push(this.width * this.height);
    } });
  }
  window.sent = [];
  const send = XMLHttpRequest.prototype.send;
  XMLHttpRequest.prototype.send = function (body) {
    const photo = body instanceof FormData ? body.get("photo") : null;
    if (photo) window.sent.push({ name: photo.name, type: photo.type, size: photo.size });
    return send.call(this, body);
  };
}"""

# The colour at the centre of each quarter of the shown photo, as the page drew it.
COLOURS = """(img) => {
  const canvas = document.createElement("canvas");
  canvas.width = 4;
  canvas.height = 4;
  const context = canvas.getContext("2d");
  context.drawImage(img, 0, 0, 4, 4);
  const at = (x, y) => [...context.getImageData(x, y, 1, 1).data.slice(0, 3)];
  return { "top-left": at(1, 1), "top-right": at(2, 1), "bottom-left": at(1, 2),
           "bottom-right": at(2, 2) };
}"""


# The centre of each quarter on a 4 x 4 picture of the photo (as COLOURS reads it).
CENTRES = {"top-left": (1, 1), "top-right": (2, 1), "bottom-left": (1, 2), "bottom-right": (2, 2)}


@pytest.fixture(scope="module")
def turned_photo(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The upright photo stored a quarter turn back, with EXIF orientation 6, as a JPEG."""
    width, height = UPRIGHT
    upright = Image.new("RGB", UPRIGHT, REST)
    upright.paste(QUARTERS["top-left"], (0, 0, width // 2, height // 2))
    upright.paste(QUARTERS["top-right"], (width // 2, 0, width, height // 2))
    upright.paste(QUARTERS["bottom-left"], (0, height // 2, width // 2, height))
    stored = upright.transpose(Image.Transpose.ROTATE_90)  # a quarter anticlockwise
    exif = Image.Exif()
    exif[EXIF_ORIENTATION] = ROTATE_90_CW
    path = tmp_path_factory.mktemp("photos") / "IMG_0001.jpg"
    stored.save(path, quality=90, exif=exif)
    with Image.open(path) as check:  # what the photo shows is the upright one
        assert ImageOps.exif_transpose(check).size == UPRIGHT
    return path


def nearest(colour: list[int]) -> str:
    """The quarter whose colour is nearest (JPEG and scaling blur the edges)."""
    colours = {**QUARTERS, "bottom-right": REST}
    return min(
        colours, key=lambda q: sum((a - b) ** 2 for a, b in zip(colour, colours[q], strict=True))
    )


def test_a_48_mp_turned_photo_goes_up_small_and_upright(
    server: str, api: httpx2.Client, iphone: Phone, turned_photo: Path
) -> None:
    # The search is started over the API; the iPhone joins it with the link.
    play.joined_by_link(api, iphone)
    expect(iphone.get_by_test_id("photo-input")).to_be_attached()
    iphone.evaluate(SPY)
    iphone.get_by_test_id("photo-input").set_input_files(turned_photo)

    view = iphone.get_by_test_id("photo-view")
    long_side, short_side = STORED_SIDE, STORED_SIDE * UPRIGHT[0] // UPRIGHT[1]
    expect(view).to_have_attribute("data-photo-width", str(short_side))
    expect(view).to_have_attribute("data-photo-height", str(long_side))
    # The phone made the JPEG itself, from a canvas of the sent size and none larger...
    [sent] = iphone.evaluate("() => window.sent")
    assert (sent["name"], sent["type"]) == ("photo.jpg", "image/jpeg"), sent
    assert sent["size"] < turned_photo.stat().st_size, sent
    areas = iphone.evaluate("() => window.canvasAreas")
    assert max(areas) == short_side * long_side <= CANVAS_CAP, areas
    # ...upright, as the phone shows it (its own copy: WebKit may draw a picture it has not
    # decoded yet as transparent, so the colours are read until they are drawn)...
    iphone.wait_until(
        lambda: view.locator("img").evaluate(COLOURS),
        lambda shown: all(nearest(colour) == quarter for quarter, colour in shown.items()),
        "the shown photo, upright",
    )
    # ...and as the server stores it: it keeps a photo without EXIF as it comes.
    with Image.open(io.BytesIO(play.stored_photo(server, iphone, "joiner"))) as kept:
        assert kept.size == (short_side, long_side)
        small = kept.convert("RGB").resize((4, 4))
        # An RGB image's pixel is a tuple: Pillow's getpixel is typed for every mode.
        colours = {q: list(small.getpixel(xy)) for q, xy in CENTRES.items()}  # type: ignore[arg-type]
    assert {quarter: nearest(colour) for quarter, colour in colours.items()} == {
        quarter: quarter for quarter in colours
    }, colours
