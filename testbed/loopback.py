"""The app on a loopback port, for the browser tests (``tests/e2e``): it lives in
:mod:`deploy.replica`, which ``make run-cluster`` starts too (deploy imports nothing from
the test bed; the test bed imports from deploy)."""

from deploy.replica import Server, free_port, serve

__all__ = ["Server", "free_port", "serve"]
