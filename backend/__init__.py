"""Buddy Search web service: pairs two phones, keeps their photos and taps, solves, draws.

Data flows one way: routes (``api``) -> services (``sessions``) -> storage and the solver
(``shared_solver``). The ASGI app is ``backend.main:app``.
"""

__version__ = "0.1.0"
