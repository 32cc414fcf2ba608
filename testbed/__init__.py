"""Scenes with ground truth for the tests, the benchmarks and the demo; not shipped in the app.

Synthetic two-camera scenes (phones facing each other across a venue, and other kinds) and
the calibrated Middlebury temple views, with the taps fingers would make on them; and one
phone's client of the session API (:mod:`testbed.client`). Every scene is drawn in one world
frame: metres, x right, y down, z forward, as a camera at rest sees it (docs/geometry.md,
"Words and conventions").
"""
