"""Exact few-landmark solvers: one problem per file, every real solution, no ranking.

Each takes checked landmarks (and what is known about the friends) and returns all the
geometries that fit them exactly; choosing among them is :mod:`..estimation`'s job.
"""
