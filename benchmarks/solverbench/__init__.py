"""The solver benchmark's parts; ``benchmarks/solver.py`` is its command.

- ``common``: seeds, what one trial of one method gives, summaries, running ``solve``
- ``phones``: phone scenes: accuracy against OpenCV, zoomed photos, coverage case by case
- ``ranking``: exact input with several roots: is the answer the true one
- ``facing``: the simple facing scenes: accuracy against OpenCV, every projective method
- ``speed``: interleaved timings of ``solve`` and the five-landmark solver

Each section's module also writes its tables and checks its targets; ``solver.py`` runs the
sections and puts the report together.
"""
