"""Debian's nginx with the project's own ``deploy/nginx.conf``, as a plain process.

The shipped file is written for the official image in Compose: ports 80 and 443, the
replicas found by Docker's DNS, the certificate and logs at the image's paths. Here it is
templated only there: loopback ports, the replicas' loopback addresses, this run's folder
for the certificate, logs, pid and temporary files. Every other line is the shipped one.

The template is a few exact substitutions, each required to match once, rather than an
nginx config library: crossplane, Python's, has had no release since 2022 and drops the
file's comments, and `nginx -t` (tests/test_deploy.py) checks the result anyway.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import httpx2

SHIPPED = Path(__file__).with_name("nginx.conf")
STARTUP_SECONDS = 20.0
STOP_SECONDS = 10.0
# The paths nginx writes to, compiled into Debian's package under /var/lib/nginx and /run:
# not writable by anyone but root, and shared by every nginx of the machine.
TEMPORARY = ("client_body", "proxy", "fastcgi", "uwsgi", "scgi")


@dataclass(frozen=True)
class Listen:
    """Where this nginx listens and what it serves TLS with."""

    host: str
    http_port: int
    https_port: int
    certificate: Path
    key: Path


def binary() -> str:
    """Debian's nginx (``make nginx`` installs it)."""
    # /usr/sbin is on root's PATH only: anyone else finds Debian's nginx there too.
    found = shutil.which("nginx", path=f"{os.environ.get('PATH', '')}:/usr/sbin")
    if found is None:
        raise RuntimeError("nginx is not installed: run `make nginx` (or make test)")
    return found


def _replace(text: str, pattern: str, new: str, what: str) -> str:
    """``pattern`` (a whole directive) replaced by ``new`` exactly once, or an error: a
    change to the shipped file must not leave a machine-specific line untemplated."""
    result, count = re.subn(pattern, lambda _: new, text, flags=re.MULTILINE)
    if count != 1:
        raise ValueError(f"deploy/nginx.conf: {what} found {count} times, expected once")
    return result


def render(listen: Listen, replicas: Sequence[str], folder: Path, text: str | None = None) -> str:
    """The shipped config (or ``text``) for this machine: ``replicas`` as ``host:port``."""
    text = SHIPPED.read_text() if text is None else text
    https = f"{listen.host}:{listen.https_port}"
    servers = "".join(f"server {address};\n        " for address in replicas).rstrip()
    text = _replace(text, r"^\s*resolver [^;]*;\n", "", "the resolver (Docker's DNS)")
    text = _replace(text, r"server backend:\d+ resolve;", servers, "the replicas' server line")
    text = _replace(text, r"listen 80;", f"listen {listen.host}:{listen.http_port};", "port 80")
    text = _replace(text, r"listen 443 ssl;", f"listen {https} ssl;", "port 443")
    text = _replace(
        text,
        r"return 301 https://\$host\$request_uri;",
        f"return 301 https://$host:{listen.https_port}$request_uri;",
        "the redirect to port 443",
    )
    text = _replace(
        text,
        r"ssl_certificate /etc/nginx/tls/\S+;",
        f"ssl_certificate {listen.certificate};",
        "the certificate",
    )
    text = _replace(
        text,
        r"ssl_certificate_key /etc/nginx/tls/\S+;",
        f"ssl_certificate_key {listen.key};",
        "the key",
    )
    text = _replace(
        text, r"access_log /var/log/nginx/access.log", f"access_log {folder / 'access.log'}", "log"
    )
    paths = "".join(f"\n    {kind}_temp_path {folder / kind};" for kind in TEMPORARY)
    return _replace(text, r"^http \{", "http {" + paths, "the http block")


def command(folder: Path, *extra: str) -> list[str]:
    """nginx on ``folder/nginx.conf``, in the foreground, its pid and errors in ``folder``."""
    globals_ = f"daemon off; pid {folder / 'nginx.pid'};"
    conf = str(folder / "nginx.conf")
    return [
        binary(),
        "-p",
        str(folder),
        "-c",
        conf,
        "-e",
        str(folder / "error.log"),
        "-g",
        globals_,
        *extra,
    ]


def check(config: str) -> subprocess.CompletedProcess[str]:
    """``nginx -t`` on ``config`` (a rendered file), in a throwaway folder."""
    with tempfile.TemporaryDirectory(prefix="buddy-nginx-test-") as name:
        folder = Path(name)
        (folder / "nginx.conf").write_text(config)
        return subprocess.run(
            command(folder, "-t"), capture_output=True, text=True, timeout=30, check=False
        )


class PortTakenError(RuntimeError):
    """nginx could not bind a port of its ``Listen``: another process took it between its
    choice and nginx's start (a free port is only free when it is looked at)."""


@dataclass(frozen=True)
class Nginx:
    pid: int
    folder: Path


@contextmanager
def run(listen: Listen, replicas: Sequence[str]) -> Iterator[Nginx]:
    """nginx serving the shipped config on ``listen``, in front of ``replicas``, until the
    block ends (then stopped, its folder deleted). Its folder is world-readable: when root
    starts it, its workers run as ``nobody`` and write their temporary files there."""
    folder = Path(tempfile.mkdtemp(prefix="buddy-nginx-"))
    folder.chmod(0o755)
    (folder / "nginx.conf").write_text(render(listen, replicas, folder))
    process = subprocess.Popen(
        command(folder),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,  # Ctrl+C reaches the launcher, which stops nginx in order
    )
    try:
        _wait_until_listening(listen, process, folder)
        yield Nginx(process.pid, folder)
    finally:
        process.terminate()  # SIGTERM: nginx's fast shutdown, streams closed at once
        try:
            process.wait(timeout=STOP_SECONDS)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(timeout=STOP_SECONDS)
        shutil.rmtree(folder, ignore_errors=True)


def _wait_until_listening(listen: Listen, process: subprocess.Popen[bytes], folder: Path) -> None:
    """Until the plain-HTTP port answers (with its redirect)."""
    url = f"http://{listen.host}:{listen.http_port}/"
    deadline = time.monotonic() + STARTUP_SECONDS
    while time.monotonic() < deadline:
        if process.poll() is not None:
            log = _log(folder)
            taken = "Address already in use" in log
            raise (PortTakenError if taken else RuntimeError)(f"nginx exited at start:\n{log}")
        try:
            httpx2.get(url, timeout=1)
            return
        except httpx2.TransportError:
            time.sleep(0.05)
    raise RuntimeError(f"nginx did not answer in {STARTUP_SECONDS:g} s:\n{_log(folder)}")


def _log(folder: Path) -> str:
    log = folder / "error.log"
    return log.read_text()[-3000:] if log.exists() else "(no error.log)"
