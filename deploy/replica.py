"""One replica of the app: a child uvicorn process on a free loopback port, for
``make run-cluster`` (:mod:`deploy.cluster`) and for the live tests and the benchmarks,
which need a real server rather than an in-process client."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import httpx2

ROOT = Path(__file__).resolve().parents[1]
STARTUP_SECONDS = 30.0


@dataclass(frozen=True)
class Server:
    base_url: str
    pid: int


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


@contextmanager
def serve(
    folder: Path, env: dict[str, str] | None = None, port: int | None = None
) -> Iterator[Server]:
    """uvicorn serving ``backend.main:app`` on 127.0.0.1 (on ``port``, else a free one),
    SQLite in ``folder`` unless ``env`` says otherwise; terminated on exit. Its output goes
    to ``folder/uvicorn.log`` (appended: a server restarted on the same folder and port
    keeps the first one's), shown if it fails to start."""
    port = port or free_port()
    environment = os.environ | {"BUDDY_DATABASE_URL": f"sqlite:///{folder / 'buddy.db'}"}
    command = [sys.executable, "-m", "uvicorn", "backend.main:app", "--host", "127.0.0.1"]
    command += ["--port", str(port), "--no-access-log", "--timeout-graceful-shutdown", "3"]
    log_path = folder / "uvicorn.log"
    with log_path.open("ab") as log:
        process = subprocess.Popen(
            command, cwd=ROOT, env=environment | (env or {}), stdout=log, stderr=log
        )
    server = Server(f"http://127.0.0.1:{port}", process.pid)
    try:
        _wait_until_healthy(server, process, log_path)
        yield server
    finally:
        process.terminate()
        try:
            process.wait(timeout=20)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(timeout=20)


def _wait_until_healthy(server: Server, process: subprocess.Popen[bytes], log: Path) -> None:
    deadline = time.monotonic() + STARTUP_SECONDS
    while time.monotonic() < deadline:
        try:
            if httpx2.get(f"{server.base_url}/healthz", timeout=1).status_code == 200:
                return
        except httpx2.TransportError:
            pass
        if process.poll() is not None:
            raise RuntimeError(f"uvicorn exited at start:\n{log.read_text()}")
        time.sleep(0.1)
    raise RuntimeError(f"uvicorn did not answer /healthz in {STARTUP_SECONDS:g} s")
