"""The slow-phone benchmark's parts (``benchmarks/slow_phone.py``): watchers inside the page,
one phone's run at one CPU throttling rate, and the app's JavaScript as a phone loads it."""
