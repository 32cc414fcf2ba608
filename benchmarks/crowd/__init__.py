"""The load benchmark's parts; ``benchmarks/load.py`` is its command.

- ``people``: people's pauses, and what their phones send (photos, taps)
- ``recorder``: the calls' names, and what a phase measured
- ``phone``: one phone (its client, calls, event stream, the state it shows)
- ``driver``: both phones of every session, step by step
- ``phases``: costs, quiet server, idle streams, load
- ``server``: the server's processes, their CPU and memory (/proc), its database
- ``options``: what a run was asked to do
- ``run``: a run, from server start to the results
- ``findings``, ``preamble``, ``sections``: the Markdown report
"""
