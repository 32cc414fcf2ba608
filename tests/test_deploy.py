"""docker-compose.yml, the Dockerfile and deploy/nginx.conf, checked by real tools and
against the app and each other.

No Docker engine runs here, so no image is built. What can run does: `nginx -t` on the
shipped config, Debian's nginx serving it in front of a recording stand-in for the app,
the compose file validated against the Compose specification's schema (check-jsonschema's
copy; Debian's docker-compose is v1, which rejects today's spec), and the Dockerfile read
by BuildKit's own parser (the ``dockerfile`` package). The cluster tests
(tests/backend/test_cluster.py) run the same config in front of real replicas.
"""

from __future__ import annotations

import ast
import json
import re
import ssl
import subprocess
import sys
import threading
import tomllib
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from importlib import metadata
from pathlib import Path
from urllib.parse import urlsplit

import dockerfile
import httpx2
import pytest
import yaml
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name
from sqlalchemy.engine import make_url

from backend.settings import Settings
from deploy import nginx, tls
from deploy.replica import free_port

ROOT = Path(__file__).parents[1]
COMPOSE = yaml.safe_load((ROOT / "docker-compose.yml").read_text())
SERVICES = COMPOSE["services"]
BACKEND, POSTGRES, NGINX = (SERVICES[name] for name in ("backend", "postgres", "nginx"))
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
DEFAULTS = {name: field.default for name, field in Settings.model_fields.items()}
SHIPPED = nginx.SHIPPED.read_text()
EVENTS_PATH = "/api/sessions/Xk3_f9-2/events"  # the app's event stream route, filled in


def stages() -> list[list[dockerfile.Command]]:
    """The Dockerfile's instructions, one list per stage (each FROM starts one)."""
    found: list[list[dockerfile.Command]] = []
    for command in dockerfile.parse_file(str(ROOT / "Dockerfile")):
        if command.cmd == "FROM":
            found.append([])
        found[-1].append(command)
    return found


def runtime(name: str) -> list[dockerfile.Command]:
    """The final stage's ``name`` instructions (BuildKit spells them in capitals)."""
    return [command for command in stages()[-1] if command.cmd == name.upper()]


(CMD,) = runtime("cmd")
APP_PORT = int(CMD.value[CMD.value.index("--port") + 1])


# --- real tools -----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def certificate(tmp_path_factory: pytest.TempPathFactory) -> tls.Certificate:
    return tls.made_at_start_up(tmp_path_factory.mktemp("tls"), ["127.0.0.1"])


@pytest.fixture(scope="module")
def trusted(certificate: tls.Certificate) -> ssl.SSLContext:
    """What a client that trusts the certificate verifies connections with."""
    return ssl.create_default_context(cafile=certificate.authority)


def test_nginx_accepts_the_shipped_config(certificate: tls.Certificate) -> None:
    """`nginx -t` on deploy/nginx.conf as make run-cluster templates it (loopback ports and
    replicas instead of Docker's DNS name, this run's paths); a broken line fails it."""
    listen = nginx.Listen("127.0.0.1", 8080, 8443, certificate.certificate, certificate.key)
    with_folder = Path(certificate.certificate).parent
    config = nginx.render(listen, ["127.0.0.1:8001", "127.0.0.1:8002"], with_folder)
    done = nginx.check(config)
    assert done.returncode == 0, done.stderr
    assert "test is successful" in done.stderr
    broken = nginx.check(config.replace("proxy_buffering off;", "proxy_buffering maybe;"))
    assert broken.returncode != 0
    assert "proxy_buffering" in broken.stderr


def test_rendering_refuses_a_config_it_cannot_template() -> None:
    """A machine-specific line the template does not know (a changed port) is an error, not
    a config left pointing at Docker's addresses."""
    listen = nginx.Listen("127.0.0.1", 8080, 8443, Path("c.pem"), Path("k.pem"))
    with pytest.raises(ValueError, match="port 443"):
        nginx.render(
            listen,
            ["127.0.0.1:1"],
            Path("x"),
            SHIPPED.replace("listen 443 ssl;", "listen 8443 ssl;"),
        )


def compose_check(path: Path) -> subprocess.CompletedProcess[str]:
    command = [str(Path(sys.executable).with_name("check-jsonschema"))]
    command += ["--builtin-schema", "vendor.compose-spec", str(path)]
    return subprocess.run(command, capture_output=True, text=True, timeout=60, check=False)


def test_the_compose_file_follows_the_compose_specification(tmp_path: Path) -> None:
    """Validated against the Compose specification's JSON schema; a misspelt key fails."""
    done = compose_check(ROOT / "docker-compose.yml")
    assert done.returncode == 0, done.stdout + done.stderr
    misspelt = tmp_path / "docker-compose.yml"
    misspelt.write_text(
        (ROOT / "docker-compose.yml").read_text().replace("depends_on:", "depend_on:", 1)
    )
    assert compose_check(misspelt).returncode != 0


# --- the shipped nginx.conf, run in front of a recording stand-in for the app -----------------


@contextmanager
def serving(
    answer: Callable[[BaseHTTPRequestHandler], tuple[int, dict[str, str]]],
    body: bytes = b"",
) -> Iterator[int]:
    """A loopback HTTP/1.1 server (in threads, logging nothing), its port: ``answer`` gives
    each GET's status and headers; each answer's body is ``body``."""

    class Handler(BaseHTTPRequestHandler):
        protocol_version = "HTTP/1.1"

        def do_GET(self) -> None:
            status, headers = answer(self)
            self.send_response(status)
            for name, value in {**headers, "Content-Length": str(len(body))}.items():
                self.send_header(name, value)
            self.end_headers()
            self.wfile.write(body)

        def log_message(self, *args: object) -> None:
            pass

    server = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        yield server.server_address[1]
    finally:
        server.shutdown()
        server.server_close()


Seen = list[dict[str, str]]  # what a stand-in for the app received: version, path, headers


@pytest.fixture
def proxied(certificate: tls.Certificate) -> Iterator[tuple[str, Seen, nginx.Nginx]]:
    """nginx with the shipped config, its replicas one stand-in that answers every request
    200 and keeps what it received; the HTTPS base URL."""
    seen: Seen = []

    def record(request: BaseHTTPRequestHandler) -> tuple[int, dict[str, str]]:
        headers = {name.lower(): value for name, value in request.headers.items()}
        seen.append({"version": request.request_version, "path": request.path, **headers})
        kind = "text/event-stream" if request.path == EVENTS_PATH else "application/json"
        return 200, {"Strict-Transport-Security": "max-age=1", "Content-Type": kind}

    listen = nginx.Listen(
        "127.0.0.1", free_port(), free_port(), certificate.certificate, certificate.key
    )
    body = json.dumps({"answer": list(range(500))}).encode()  # 2.4 kB: worth compressing
    with serving(record, body) as port, nginx.run(listen, [f"127.0.0.1:{port}"]) as running:
        yield f"https://127.0.0.1:{listen.https_port}", seen, running


@pytest.mark.parametrize("path", ["/", "/join/48291375", EVENTS_PATH, "/api/sessions/x/photo"])
def test_every_request_reaches_the_app_with_the_phones_address_host_and_scheme(
    proxied: tuple[str, Seen, nginx.Nginx], trusted: ssl.SSLContext, path: str
) -> None:
    """In every location: HTTP/1.1 with no "Connection: close" (kept-alive connections,
    streaming), the Host with the port the phone used (join links point back to it), and
    X-Forwarded-For/Proto for uvicorn --proxy-headers, the address being the one nginx saw,
    never one the client names (the app counts failed join codes per address)."""
    base, received, _ = proxied
    answer = httpx2.get(
        f"{base}{path}",
        headers={"X-Forwarded-For": "203.0.113.7"},
        verify=trusted,
    )
    assert answer.status_code == 200
    (seen,) = received
    assert seen["version"] == "HTTP/1.1"
    assert seen.get("connection", "") != "close"
    assert seen["host"] == urlsplit(base).netloc
    assert seen["x-forwarded-for"] == "127.0.0.1"
    assert seen["x-forwarded-proto"] == "https"
    # One HSTS header, nginx's: the app's copy is dropped.
    assert answer.headers.get_list("Strict-Transport-Security") == ["max-age=31536000"]
    # nginx compresses answers, asking the replicas for plain ones; an event stream the
    # replica gzips itself, event by event: it is asked with the phone's Accept-Encoding,
    # and nginx passes it on as it comes (this stand-in's, plain).
    streamed = answer.headers["content-type"] == "text/event-stream"
    asked = answer.request.headers["accept-encoding"]
    assert "gzip" in asked
    assert seen.get("accept-encoding") == (asked if streamed else None)
    assert answer.headers.get("content-encoding") == (None if streamed else "gzip")


def test_nginx_logs_paths_without_their_tokens(
    proxied: tuple[str, Seen, nginx.Nginx], trusted: ssl.SSLContext
) -> None:
    base, _, running = proxied
    httpx2.get(f"{base}{EVENTS_PATH}?token=s3cret-t0ken", verify=trusted)
    log = running.folder / "access.log"
    for _ in range(50):  # nginx writes the line after the answer
        if log.exists() and EVENTS_PATH in log.read_text():
            break
        threading.Event().wait(0.05)
    assert EVENTS_PATH in log.read_text()
    assert "s3cret-t0ken" not in log.read_text()


def test_with_no_replica_up_nginx_answers_in_the_apps_error_shape(
    certificate: tls.Certificate, trusted: ssl.SSLContext
) -> None:
    """The phone app shows the message of {"error": {"code", "message"}}: nginx's own
    refusal when no replica answers has that shape too."""
    listen = nginx.Listen(
        "127.0.0.1", free_port(), free_port(), certificate.certificate, certificate.key
    )
    with nginx.run(listen, [f"127.0.0.1:{free_port()}"]):
        answer = httpx2.post(f"https://127.0.0.1:{listen.https_port}/api/sessions", verify=trusted)
    assert answer.status_code == 503
    assert answer.headers["content-type"] == "application/json"
    assert answer.json()["error"]["code"] == "service_unavailable"
    assert answer.json()["error"]["message"].endswith(".")


# --- docker-compose.yml agrees with the app, the Dockerfile and nginx.conf -------------------


def test_compose_sets_only_real_settings(monkeypatch: pytest.MonkeyPatch) -> None:
    """Settings ignore unknown variables, so a misspelt BUDDY_DATABASE_URI would leave every
    replica on a SQLite file of its own: phones on different replicas would never meet."""
    settings = {name for name in BACKEND["environment"] if name.startswith("BUDDY_")}
    assert {"BUDDY_DATABASE_URL", "BUDDY_PUBLIC_URL"} <= settings
    assert settings <= {f"BUDDY_{name.upper()}" for name in Settings.model_fields}


def test_the_database_url_reaches_the_postgres_service_with_psycopg() -> None:
    """psycopg 3 (plain postgresql:// means psycopg2, not installed), the postgres service's
    host, user and database, and the very same password setting as that service."""
    url = make_url(BACKEND["environment"]["BUDDY_DATABASE_URL"])
    database = POSTGRES["environment"]
    assert url.drivername == "postgresql+psycopg"
    assert (url.host, url.port) == ("postgres", 5432)
    assert (url.username, url.database) == (database["POSTGRES_USER"], database["POSTGRES_DB"])
    assert url.password == database["POSTGRES_PASSWORD"]  # the same ${...:-default}


def test_postgres_is_ready_before_the_app_and_keeps_its_data() -> None:
    """The app migrates the database at start-up, so it starts once pg_isready answers (as
    the app's user: as "root" it logs a refusal every 5 s); the data is in a named volume."""
    check = POSTGRES["healthcheck"]["test"]
    assert check[check.index("-U") + 1] == POSTGRES["environment"]["POSTGRES_USER"]
    assert BACKEND["depends_on"]["postgres"]["condition"] == "service_healthy"
    assert "pgdata:/var/lib/postgresql/data" in POSTGRES["volumes"]
    assert "pgdata" in COMPOSE["volumes"]


def test_two_replicas_reachable_only_through_nginx_on_the_port_they_listen_on() -> None:
    """Two replicas without published ports (only nginx sends the X-Forwarded-* headers they
    trust) or a container name (two containers cannot share one); nginx's upstream is the
    backend service on the port of the image's CMD and EXPOSE."""
    assert BACKEND["deploy"]["replicas"] == 2
    assert "ports" not in BACKEND
    assert "container_name" not in BACKEND
    assert [name for name, service in SERVICES.items() if service.get("ports")] == ["nginx"]
    assert NGINX["depends_on"]["backend"]["condition"] == "service_healthy"
    assert f"server backend:{APP_PORT} resolve;" in SHIPPED
    assert [command.value for command in runtime("expose")] == [(str(APP_PORT),)]


def test_nginx_gets_its_config_ports_and_certificate_where_the_config_says() -> None:
    """The shipped config mounted as nginx's; the published ports lead to the ports it
    listens on (80: the redirect, 443: TLS); the certificate and key files, required
    settings, mounted at the paths it names."""
    volumes = [volume.rsplit(":", 2) for volume in NGINX["volumes"]]
    mounts = {inside: outside for outside, inside, _ in volumes}
    assert mounts["/etc/nginx/nginx.conf"] == "./deploy/nginx.conf"
    for directive, setting in (
        ("ssl_certificate", "TLS_CERTIFICATE"),
        ("ssl_certificate_key", "TLS_CERTIFICATE_KEY"),
    ):
        (path,) = re.findall(rf"^\s*{directive}\s+([^\s;]+);", SHIPPED, re.M)
        assert mounts[path].startswith(f"${{{setting}:?")
    published = {int(port.rsplit(":", 1)[1]) for port in NGINX["ports"]}
    assert published == {80, 443}
    assert "listen 80;" in SHIPPED
    assert "listen 443 ssl;" in SHIPPED


# --- Dockerfile (BuildKit's parser) -----------------------------------------------------------


def test_the_image_runs_uvicorn_as_a_user_behind_the_proxy() -> None:
    """The exec form (in the shell form /bin/sh is process 1 and passes no SIGTERM on);
    not root; uvicorn serves backend.main:app on all interfaces, takes the phone's address
    and https from nginx's headers, keeps no access log (tokens in URLs) and stops in
    seconds though event streams never end."""
    assert CMD.json
    command = list(CMD.value)
    assert command[:2] == ["uvicorn", "backend.main:app"]
    assert command[command.index("--host") + 1] == "0.0.0.0"
    assert "--proxy-headers" in command
    assert command[command.index("--forwarded-allow-ips") + 1] == "*"
    assert "--no-access-log" in command
    assert float(command[command.index("--timeout-graceful-shutdown") + 1]) <= 5
    (user,) = [command.value[0] for command in runtime("user")][-1:]
    assert user.split(":")[0] not in ("root", "0")


def test_the_healthcheck_asks_healthz_and_fails_when_the_database_does_not_answer() -> None:
    """The image's health (which nginx waits for) is GET /healthz on the app's port; it
    answers 503 when the database is gone, and the check must then fail, or nginx keeps
    sending phones to a replica that can only refuse them."""
    (check,) = runtime("healthcheck")
    assert check.json
    assert check.value[0] == "CMD"
    program, flag, code = check.value[1:]
    assert program == "python"
    assert f"http://127.0.0.1:{APP_PORT}/healthz" in code
    statuses = {"/healthz": 200}  # a stand-in for the app: /healthz answers this, else 404
    with serving(lambda request: (statuses.get(request.path, 404), {})) as port:
        for status, healthy in ((200, True), (503, False)):
            statuses["/healthz"] = status
            probe = [sys.executable, flag, code.replace(f":{APP_PORT}/", f":{port}/")]
            run = subprocess.run(probe, check=False, capture_output=True, timeout=20)
            assert (run.returncode == 0) == healthy, (status, run.stderr.decode())


def test_the_image_builds_the_phone_app_with_node_and_serves_it() -> None:
    """A Node stage (a version package.json accepts) runs `npm ci` then `npm run build`; the
    runtime copies its dist/ to where the app looks by default (BUDDY_FRONTEND_DIR)."""
    node = stages()[0]
    image, _, name = node[0].value
    engines = json.loads((ROOT / "frontend" / "package.json").read_text())["engines"]["node"]
    assert int(image.split(":")[1].split("-")[0]) >= int(engines.lstrip(">= ").split(".")[0])
    runs = [command.value[0] for command in node if command.cmd == "RUN"]
    assert runs.index("npm run build") > next(
        i for i, run in enumerate(runs) if run.startswith("npm ci")
    )
    (workdir,) = [command.value[0] for command in node if command.cmd == "WORKDIR"]
    (copied,) = [command for command in runtime("copy") if command.flags == (f"--from={name}",)]
    assert copied.value == (f"{workdir}/dist", DEFAULTS["frontend_dir"])
    assert [command.value for command in runtime("workdir")] == [("/app",)]


def test_the_runtime_is_slim_python_with_the_app_and_without_test_packages() -> None:
    """python:3.11-slim; pyproject's runtime dependencies only (not pytest, mypy,
    Playwright); every package of the project copied (one left out would be an ImportError
    at start-up)."""
    assert stages()[-1][0].value[0].startswith("python:3.11-slim")
    installs = [command.value[0] for command in runtime("run") if "pip install" in command.value[0]]
    assert installs
    # The runtime lock (pyproject's dependencies, hashes checked), not the test extras.
    sources = {
        command.value[-1]: command.value[0] for command in runtime("copy") if not command.flags
    }
    locks = [sources[run.split("-r ")[1].split()[0]] for run in installs]
    assert locks == ["requirements/runtime.txt"]
    assert all("--require-hashes" in run and "[test]" not in run for run in installs)
    copied = {command.value[0].rstrip("/") for command in runtime("copy") if not command.flags}
    setuptools = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    for pattern in setuptools["packages"]["find"]["include"]:
        assert pattern.rstrip("*") in copied, pattern


def test_the_build_context_holds_only_what_the_dockerfile_copies() -> None:
    """.dockerignore is an allow-list: everything out (`*`), then back in what a COPY names
    (and pyproject.toml: the project's metadata, no secret), so .env (the database
    password), .venv and var/ never enter an image."""
    lines = [line.strip() for line in (ROOT / ".dockerignore").read_text().splitlines()]
    patterns = [line for line in lines if line and not line.startswith("#")]
    assert patterns[0] == "*"
    allowed = {pattern[1:].rstrip("/") for pattern in patterns if pattern.startswith("!")}
    sources = {
        source.rstrip("/")
        for command in dockerfile.parse_file(str(ROOT / "Dockerfile"))
        if command.cmd == "COPY" and not command.flags
        for source in command.value[:-1]
    }

    def within(path: str, folder: str) -> bool:
        return path == folder or path.startswith(f"{folder}/")

    assert all(any(within(source, entry) for entry in allowed) for source in sources)
    unused = {entry for entry in allowed if not any(within(s, entry) for s in sources)}
    assert unused <= {"pyproject.toml"}


# The files of this project's modules that the app loads when it starts (its Alembic
# migrations are read from their folder), and the database driver the compose URL loads:
# printed by a fresh interpreter, so that nothing this test run imported counts.
_LOADED_AT_START = """
import sys
from sqlalchemy.engine import make_url
import backend.main
from backend.storage.database import MIGRATIONS
print(make_url(sys.argv[1]).get_dialect().import_dbapi().__name__)
for name, module in list(sys.modules.items()):
    if name.split(".")[0] in ("backend", "shared_solver"):
        print(module.__file__)
for path in MIGRATIONS.rglob("*.py"):
    print(path)
"""


def runtime_distributions() -> set[str]:
    """pyproject's runtime dependencies (with their extras) and, as installed here, all that
    they require in turn on Linux: what the image's `pip install` brings."""
    todo = [(Requirement(spec), "") for spec in PROJECT["dependencies"]]
    seen: set[tuple[str, frozenset[str]]] = set()
    while todo:
        requirement, extra = todo.pop()
        marker = requirement.marker
        if marker is not None and not marker.evaluate({"extra": extra, "sys_platform": "linux"}):
            continue
        key = (canonicalize_name(requirement.name), frozenset(requirement.extras))
        if key in seen:
            continue
        seen.add(key)
        try:
            specs = metadata.requires(requirement.name) or []
        except metadata.PackageNotFoundError:
            specs = []  # not installed here: what it requires is unknown, and not checked
        for spec in specs:
            todo += [(Requirement(spec), extra) for extra in requirement.extras or {""}]
    return {name for name, _ in seen}


def imported_names(source: Path) -> set[str]:
    """Top-level names of the absolute imports in a Python file."""
    names = set()
    for node in ast.walk(ast.parse(source.read_text())):
        if isinstance(node, ast.Import):
            names |= {alias.name.split(".")[0] for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            names.add(node.module.split(".")[0])
    return names


def test_deploy_imports_nothing_from_the_test_bed_or_the_tests() -> None:
    """deploy/ ships (make run-cluster, the image's topology): the tests and the test bed
    import it, never the other way round."""
    for source in sorted((ROOT / "deploy").glob("*.py")):
        assert imported_names(source).isdisjoint({"testbed", "tests", "benchmarks"}), source


def test_the_image_installs_everything_the_app_imports() -> None:
    """The image installs pyproject's runtime dependencies and nothing else (what was put
    into the development venv by hand does not count): every package the app's code imports
    when it starts, and the driver of the compose database URL with a libpq for it, must
    come from them, or each replica stops at start-up."""
    url = BACKEND["environment"]["BUDDY_DATABASE_URL"]
    probe = [sys.executable, "-c", _LOADED_AT_START, url]
    driver, *files = subprocess.run(
        probe, cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout.splitlines()
    names = {driver}.union(*(imported_names(Path(file)) for file in files))
    providers = metadata.packages_distributions()
    needed = {canonicalize_name(dist) for name in names for dist in providers.get(name, [])}
    needed.discard(canonicalize_name(PROJECT["name"]))  # backend, shared_solver: copied
    assert {"fastapi", "sqlalchemy", "psycopg"} <= needed  # the probe saw the app
    installed = runtime_distributions()
    assert needed - installed == set()
    # psycopg needs a libpq: psycopg[binary] ships one, else the image must install it.
    libpq = {"psycopg-binary", "psycopg-c"} & installed
    assert libpq or any("libpq" in command.value[0] for command in runtime("run"))
