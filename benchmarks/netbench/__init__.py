"""The network benchmark's parts (``benchmarks/network.py``): network profiles and byte
counts through the DevTools protocol, watchers inside the page, the two phones' search."""
