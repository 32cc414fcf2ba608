"""Drawing the answer: what is drawn on each photo, once, as shapes in its pixels
(:mod:`.layout` -> :mod:`.shapes`, from :mod:`.frame`, :mod:`.arrow` and :mod:`.curves`), and
OpenCV's rendering of them on the photo (:mod:`.overlay`), in the colours both phones share
(:mod:`.palette`). The phone app renders the same shapes as SVG."""
