"""The production topology without containers: nginx (TLS) -> replicas -> PostgreSQL.

``python -m deploy.cluster`` (``make run-cluster``) starts a throwaway PostgreSQL server,
two uvicorn replicas of the app on it and Debian's nginx with ``deploy/nginx.conf`` in front
of them, all on loopback ports unless told otherwise, with a certificate made at start-up
unless given one; Ctrl+C stops everything and deletes the database. The cluster tests and
the load benchmark start the same topology with :func:`cluster`.
"""

from __future__ import annotations

import argparse
import signal
import sys
import tempfile
from collections.abc import Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor
from contextlib import AbstractContextManager, ExitStack, contextmanager
from dataclasses import dataclass
from pathlib import Path
from types import FrameType
from typing import TypeVar

from backend.__main__ import lan_address
from deploy import nginx, tls
from deploy.postgres import PostgresServer
from deploy.replica import Server, free_port, serve

REPLICAS = 2
T = TypeVar("T")


# How many times free ports are chosen for nginx before its start is given up.
_PORT_TRIES = 3


@dataclass(frozen=True)
class Cluster:
    url: str  # https://host:port: what phones open
    http_url: str  # plain HTTP: answers with a redirect to ``url``
    authority: Path | None  # the certificate to trust, when it was made at start-up
    replicas: tuple[Server, ...]
    nginx: nginx.Nginx
    database_url: str


@contextmanager
def cluster(
    folder: Path,
    database_url: str,
    *,
    replicas: int = REPLICAS,
    host: str = "127.0.0.1",
    ports: tuple[int, int] = (0, 0),
    certificate: tuple[Path, Path] | None = None,
    environment: dict[str, str] | None = None,
) -> Iterator[Cluster]:
    """nginx on ``host`` (HTTP and HTTPS ``ports``; 0: a free one) in front of ``replicas``
    uvicorn processes on ``database_url``, each with its log in ``folder``; ``certificate``
    (its file and key) or one made at start-up in ``folder``. Stopped when the block ends."""
    if certificate is None:
        names = ["127.0.0.1", "localhost", *([address] if (address := lan_address()) else [])]
        made = tls.made_at_start_up(folder, names)
        certificate = (made.certificate, made.key)
        authority: Path | None = made.authority
    else:
        authority = None
    settings = {"BUDDY_DATABASE_URL": database_url, **(environment or {})}
    with ExitStack() as stack:
        starting = []
        for number in range(1, replicas + 1):
            (folder / f"replica{number}").mkdir(exist_ok=True)
            starting.append(serve(folder / f"replica{number}", settings))
        servers = started_together(stack, starting)
        addresses = [server.base_url.removeprefix("http://") for server in servers]
        # Free ports are chosen last, once the replicas have theirs, and chosen again if
        # another process takes one before nginx binds it.
        for attempt in range(_PORT_TRIES):
            http_port, https_port = (port or free_port() for port in ports)
            listen = nginx.Listen(host, http_port, https_port, *certificate)
            try:
                proxy = stack.enter_context(nginx.run(listen, addresses))
                break
            except nginx.PortTakenError:
                if all(ports) or attempt == _PORT_TRIES - 1:
                    raise
        shown = "127.0.0.1" if host == "0.0.0.0" else host
        yield Cluster(
            f"https://{shown}:{https_port}",
            f"http://{shown}:{http_port}",
            authority,
            tuple(servers),
            proxy,
            database_url,
        )


def started_together(stack: ExitStack, starting: Sequence[AbstractContextManager[T]]) -> list[T]:
    """Each context entered at once in a thread of its own (the replicas load the app in
    parallel), and exited with ``stack``; if any fails, the others are exited too."""
    with ThreadPoolExecutor(len(starting)) as pool:
        entering = [pool.submit(context.__enter__) for context in starting]
    entered, failures = [], []
    for context, future in zip(starting, entering, strict=True):
        try:
            entered.append(future.result())
            stack.push(context)
        except Exception as failure:
            failures.append(failure)
    if failures:
        raise failures[0]
    return entered


def _stop(signum: int, frame: FrameType | None) -> None:
    raise KeyboardInterrupt  # SIGTERM stops it as Ctrl+C does: everything, in order


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    parser.add_argument(
        "--host",
        default="127.0.0.1",
        help="nginx's address (default %(default)s; 0.0.0.0: the LAN too)",
    )
    parser.add_argument(
        "--https-port", type=int, default=8443, help="default %(default)s; 0: any free port"
    )
    parser.add_argument(
        "--http-port", type=int, default=8080, help="redirects to HTTPS (default %(default)s)"
    )
    parser.add_argument("--replicas", type=int, default=REPLICAS, choices=range(1, 9))
    parser.add_argument(
        "--certificate",
        type=Path,
        help="a PEM certificate (with its chain) instead of one made at start-up",
    )
    parser.add_argument("--key", type=Path, help="its private key (PEM)")
    args = parser.parse_args(argv)
    if (args.certificate is None) != (args.key is None):
        parser.error("--certificate and --key go together")
    given = (args.certificate.resolve(), args.key.resolve()) if args.certificate else None
    signal.signal(signal.SIGTERM, _stop)
    # Ctrl+C as well when started in the background, where the shell makes it ignored.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with ExitStack() as stack:
            folder = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="buddy-cluster-")))
            postgres = PostgresServer()
            stack.callback(postgres.remove)
            postgres.start()
            url = postgres.url(postgres.create_database(name="buddy"))
            running = stack.enter_context(
                cluster(
                    folder,
                    url,
                    replicas=args.replicas,
                    host=args.host,
                    ports=(args.http_port, args.https_port),
                    certificate=given,
                )
            )
            describe(running, args.host)
            signal.pause()
    except KeyboardInterrupt:
        print("\nStopped: nginx, the replicas and PostgreSQL (its data deleted).")


def describe(running: Cluster, host: str) -> None:
    port = running.url.rsplit(":", 1)[1]
    print("Buddy Search cluster is running. Stop it with Ctrl+C.")
    print(f"  open:        {running.url}  (plain HTTP {running.http_url} redirects there)")
    if host == "0.0.0.0" and (address := lan_address()):
        print(f"  on the LAN:  https://{address}:{port}")
    if running.authority is not None:
        print("  certificate: made at start-up; browsers warn about it. To verify it instead:")
        print(f"               curl --cacert {running.authority} {running.url}/healthz")
    for number, replica in enumerate(running.replicas, start=1):
        print(f"  replica {number}:   {replica.base_url} (pid {replica.pid})")
    print(f"  nginx:       pid {running.nginx.pid}, logs in {running.nginx.folder}")
    print(f"  database:    {running.database_url}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
