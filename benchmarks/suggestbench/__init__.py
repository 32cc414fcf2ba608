"""The suggestion benchmark's parts; ``benchmarks/suggestions.py`` is its command.

- ``trials``: one rendered hall: the answer from noisy taps, then for each landmark its
  band, the search along it and back, the tap checks; spots the other photo does not show
- ``sift``: the alternative measured against it: SIFT keypoints matched inside the band
- ``tables``: the report's tables and targets
"""
