"""Scenes with ground truth for the tests, the benchmarks and the demo; not shipped in the app.

Synthetic two-camera scenes (phones facing each other across a venue, and other kinds) and
the calibrated Middlebury temple views, with the taps fingers would make on them.
"""
