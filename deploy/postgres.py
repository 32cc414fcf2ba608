"""A throwaway PostgreSQL server for the tests, the load benchmark and ``make run-cluster``:
Debian's binaries, a data directory in a temporary folder, listening on a free 127.0.0.1
port; no container, nothing left behind.

PostgreSQL refuses to run as root (as CI and this machine do), so then the server runs as
the ``postgres`` OS user, which the Debian package creates.
"""

from __future__ import annotations

import contextlib
import itertools
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

import psycopg
from psycopg import sql

from deploy.replica import free_port

USER = "buddy"
PASSWORD = "test-only-password"  # a password, so URLs with one are exercised
COMMAND_SECONDS = 60


def binaries() -> Path:
    """The newest installed PostgreSQL's bin folder (``make test`` installs the package)."""
    found = sorted(Path("/usr/lib/postgresql").glob("*/bin/postgres"), key=_major)
    if not found:
        raise RuntimeError("PostgreSQL is not installed: run `make postgres` (or make test)")
    return found[-1].parent


def _major(path: Path) -> int:
    version = path.parents[1].name
    return int(version) if version.isdigit() else 0


class PostgresServer:
    """One server, initialised at once; :meth:`stop` and :meth:`start` again (a restart
    mid-test) keep its data directory and port."""

    def __init__(self, settings: dict[str, str] | None = None) -> None:
        """``settings``: server settings beyond the defaults, as ``-c name=value``."""
        self.bin = binaries()
        self.settings = {"listen_addresses": "127.0.0.1", **(settings or {})}
        self.folder = Path(tempfile.mkdtemp(prefix="buddy-postgres-"))
        self.data = self.folder / "data"
        self.port = free_port()
        self._names = itertools.count(1)
        # As root, run as postgres (chowning the folder); as anyone else, as themselves.
        self._as: list[str] = []
        if os.geteuid() == 0:
            self._as = ["runuser", "-u", "postgres", "--"]
            shutil.chown(self.folder, "postgres", "postgres")
        password_file = self.folder / "password"
        password_file.write_text(PASSWORD)
        if self._as:
            shutil.chown(password_file, "postgres", "postgres")
        self._run(
            "initdb",
            "--pgdata",
            str(self.data),
            "--username",
            USER,
            "--pwfile",
            str(password_file),
            "--auth-host",
            "scram-sha-256",
            "--auth-local",
            "trust",
            "--encoding",
            "UTF8",
            "--no-sync",  # a throwaway cluster: the server itself still fsyncs
        )

    def _run(self, program: str, *args: str) -> None:
        done = subprocess.run(
            [*self._as, str(self.bin / program), *args],
            capture_output=True,
            text=True,
            timeout=COMMAND_SECONDS,
            check=False,
        )
        if done.returncode != 0:
            log = self.folder / "postgres.log"
            raise RuntimeError(
                f"{program} failed: {done.stdout}{done.stderr}"
                + (f"\npostgres.log:\n{log.read_text()[-3000:]}" if log.exists() else "")
            )

    def start(self) -> None:
        options = f"-p {self.port} -k {self.folder}"
        options += "".join(f" -c {name}={value}" for name, value in self.settings.items())
        log = self.folder / "postgres.log"
        self._run("pg_ctl", "start", "-D", str(self.data), "-w", "-o", options, "-l", str(log))

    def stop(self, mode: str = "fast") -> None:
        """``fast``: disconnect everyone and shut down cleanly; ``immediate``: like a crash."""
        self._run("pg_ctl", "stop", "-D", str(self.data), "-w", "-m", mode)

    def remove(self) -> None:
        """Stop (if running) and delete the data directory."""
        with contextlib.suppress(RuntimeError):  # not running
            self.stop("immediate")
        shutil.rmtree(self.folder, ignore_errors=True)

    def url(self, database: str) -> str:
        """The app's ``BUDDY_DATABASE_URL`` for ``database``."""
        return f"postgresql+psycopg://{USER}:{PASSWORD}@127.0.0.1:{self.port}/{database}"

    def create_database(self, template: str | None = None, name: str | None = None) -> str:
        """A new database (empty, or a copy of ``template``); its name."""
        name = name or f"test_{next(self._names)}"
        query = sql.SQL("CREATE DATABASE {}").format(sql.Identifier(name))
        if template:
            query += sql.SQL(" TEMPLATE {}").format(sql.Identifier(template))
        self._admin(query)
        return name

    def drop_database(self, name: str) -> None:
        self._admin(sql.SQL("DROP DATABASE {} WITH (FORCE)").format(sql.Identifier(name)))

    def conninfo(self, database: str) -> str:
        """libpq's connection string for ``database`` (psycopg's, not the app's URL)."""
        return f"host=127.0.0.1 port={self.port} user={USER} password={PASSWORD} dbname={database}"

    def _admin(self, query: sql.Composed) -> None:
        with psycopg.connect(self.conninfo("postgres"), autocommit=True) as connection:
            connection.execute(query)
