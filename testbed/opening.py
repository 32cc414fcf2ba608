"""Show me's opening as the browser tests and the slow-phone benchmark time it, on the page's
own clock: the page marks the tap on Show me at its click's time stamp (``MARK_TAP``), and
the live view marks its steps (``frontend/src/live/LiveView.tsx``: the view mounted, the
camera's stream given, its first frame loaded, the first marker drawn over the video).
Scripts for a page's ``evaluate``.
"""

from __future__ import annotations

import json

STEPS = ("view-opened", "camera-started", "first-frame", "marker-drawn")

# Installed once in the page: the tap on Show me, marked at the click's own time.
MARK_TAP = """() => document.addEventListener("click", (event) => {
    if (event.target.closest('[data-testid="show-me"]'))
        performance.mark("show-me:tap", { startTime: event.timeStamp });
}, true)"""

# Each step, ms after the tap (null until both marks are there). A function, not an
# expression: the app's content security policy forbids eval.
OPENING_STEPS = f"""() => {{
    const [tap] = performance.getEntriesByName("show-me:tap");
    return Object.fromEntries({json.dumps(STEPS)}.map((name) => {{
        const [mark] = performance.getEntriesByName(`show-me:${{name}}`);
        return [name, tap && mark ? mark.startTime - tap.startTime : null];
    }}));
}}"""

# Whether the first marker is drawn (for a page's wait_for_function).
OPENED = """() => performance.getEntriesByName("show-me:marker-drawn").length > 0"""

# Forgets the last opening's marks, for the next.
FORGET = """() => performance.clearMarks()"""
