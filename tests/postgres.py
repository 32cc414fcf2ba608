"""The tests' name for the throwaway PostgreSQL server, which lives in ``deploy/postgres.py``
since ``make run-cluster`` and the load benchmark start one too."""

from deploy.postgres import PASSWORD, USER, PostgresServer, binaries

__all__ = ["PASSWORD", "USER", "PostgresServer", "binaries"]
