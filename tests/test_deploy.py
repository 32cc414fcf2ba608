"""docker-compose.yml, the Dockerfile and deploy/nginx.conf agree with the app.

No Docker engine runs where the tests run, and `docker compose` is not installed, so nothing
is built or started: each test reads the files and checks one promise that `docker compose
up` would otherwise break, often silently (an event stream held in a buffer, replicas each
on a SQLite file of its own, photos refused by the proxy).
"""

from __future__ import annotations

import ast
import json
import re
import subprocess
import sys
import threading
import tomllib
from collections.abc import Iterator
from dataclasses import dataclass, field
from http.server import BaseHTTPRequestHandler, HTTPServer
from importlib import metadata
from pathlib import Path
from types import ModuleType
from urllib.parse import urlsplit

import pytest
import yaml
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name
from sqlalchemy.engine import make_url

from backend.api.routes import events, health, photos
from backend.settings import Settings

ROOT = Path(__file__).parents[1]
COMPOSE = yaml.safe_load((ROOT / "docker-compose.yml").read_text())
SERVICES = COMPOSE["services"]
BACKEND = SERVICES["backend"]
POSTGRES = SERVICES["postgres"]
NGINX = SERVICES["nginx"]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
# The settings as the compose file leaves them (not as this machine's environment has them).
DEFAULTS = {name: field.default for name, field in Settings.model_fields.items()}


# --- docker-compose.yml ---------------------------------------------------------------------

_VARIABLE = re.compile(r"\$\$|\$\{([^}]*)\}|\$(\w+)")


def interpolate(value: str, dotenv: dict[str, str]) -> str:
    """``value`` as Compose reads it, with ``dotenv`` as the environment (.env): ``$$``,
    ``$NAME``, ``${NAME}``, ``${NAME:-default}``, ``${NAME-default}``; other forms refused
    rather than misread."""

    def substitute(match: re.Match[str]) -> str:
        if match.group(0) == "$$":
            return "$"
        if match.group(2):
            return dotenv.get(match.group(2), "")
        spec = re.fullmatch(r"(\w+)(?:(:?-)(.*))?", match.group(1))
        assert spec is not None, f"unsupported interpolation {match.group(0)}"
        name, operator, default = spec.groups()
        if operator == ":-" and not dotenv.get(name):
            return default
        if operator == "-" and name not in dotenv:
            return default
        return dotenv.get(name, "")

    return _VARIABLE.sub(substitute, value)


def environment(service: dict, dotenv: dict[str, str]) -> dict[str, str]:
    """A service's ``environment`` (mapping or list form), interpolated."""
    raw = service.get("environment", {})
    if isinstance(raw, list):
        raw = dict(item.split("=", 1) for item in raw)
    return {name: interpolate(str(value), dotenv) for name, value in raw.items()}


def published_ports(service: dict) -> list[tuple[str, int]]:
    """(host, container) of each published port, short syntax, defaults interpolated."""
    pairs = []
    for entry in service.get("ports", []):
        host, container = interpolate(str(entry), {}).rsplit(":", 1)
        pairs.append((host, int(container.split("/")[0])))
    return pairs


# --- Dockerfile -----------------------------------------------------------------------------


@dataclass
class Stage:
    image: str
    name: str | None
    instructions: list[tuple[str, str]] = field(default_factory=list)

    def all(self, keyword: str) -> list[str]:
        return [args for key, args in self.instructions if key == keyword]


def dockerfile_stages() -> list[Stage]:
    """The Dockerfile's instructions (keyword, arguments), comments dropped and continued
    lines joined, in one list per stage (each FROM starts one)."""
    lines = (ROOT / "Dockerfile").read_text().splitlines()
    text = "\n".join(line for line in lines if not line.lstrip().startswith("#"))
    stages: list[Stage] = []
    for line in re.sub(r"\\\n", " ", text).splitlines():
        if not line.strip():
            continue
        keyword, args = line.strip().split(None, 1)
        if keyword.upper() == "FROM":
            image, *alias = args.split()
            stages.append(Stage(image, alias[-1] if alias else None))
        else:
            stages[-1].instructions.append((keyword.upper(), args.strip()))
    return stages


STAGES = dockerfile_stages()
RUNTIME = STAGES[-1]


def uvicorn_command() -> list[str]:
    """The final stage's CMD, which must be the exec (JSON) form: in the shell form
    /bin/sh is process 1 and does not pass SIGTERM on, so every stop waits for a kill."""
    (cmd,) = RUNTIME.all("CMD")
    assert cmd.startswith("["), "CMD must be the exec form"
    return json.loads(cmd)


def option(command: list[str], name: str) -> str:
    assert name in command, f"the command lacks {name}: {command}"
    return command[command.index(name) + 1]


APP_PORT = int(option(uvicorn_command(), "--port"))


def healthcheck_command() -> list[str]:
    (check,) = RUNTIME.all("HEALTHCHECK")
    command = re.fullmatch(r"(?:--\S+\s+)*CMD\s+(\[.*\])", check)
    assert command is not None, f"HEALTHCHECK must be CMD [...] (exec form): {check}"
    return json.loads(command.group(1))


# --- deploy/nginx.conf ----------------------------------------------------------------------


@dataclass
class Directive:
    name: str
    args: list[str]
    block: list[Directive] | None = None

    def children(self, name: str) -> list[Directive]:
        return [child for child in self.block or [] if child.name == name]


def parse_nginx(text: str) -> Directive:
    """nginx.conf as a tree of directives (quotes removed, comments dropped)."""
    root = Directive("main", [], [])
    stack = [root]
    words: list[str] = []
    for token in re.findall(r"#[^\n]*|'[^']*'|\"[^\"]*\"|[{};]|[^\s{};'\"]+", text):
        if token.startswith("#"):
            continue
        if token in ";{":
            directive = Directive(words[0], words[1:], [] if token == "{" else None)
            assert stack[-1].block is not None
            stack[-1].block.append(directive)
            if token == "{":
                stack.append(directive)
            words = []
        elif token == "}":
            stack.pop()
        else:
            words.append(token[1:-1] if token[0] in "'\"" else token)
    assert len(stack) == 1, "unbalanced braces in nginx.conf"
    return root


NGINX_CONF = parse_nginx((ROOT / "deploy" / "nginx.conf").read_text())
(HTTP,) = NGINX_CONF.children("http")
(SERVER,) = HTTP.children("server")
(UPSTREAM,) = HTTP.children("upstream")


def location_for(uri: str) -> Directive:
    """The location nginx serves ``uri`` from: an exact match; else the longest prefix if it
    is ``^~``; else the first regular expression that matches; else the longest prefix."""
    prefixes: list[tuple[str, Directive]] = []
    for location in SERVER.children("location"):
        match location.args:
            case ["=", path] if path == uri:
                return location
            case ["^~", path] | [path] if uri.startswith(path):
                prefixes.append((path, location))
    longest = max(prefixes, key=lambda pair: len(pair[0]), default=None)
    if longest is not None and longest[1].args[0] == "^~":
        return longest[1]
    for location in SERVER.children("location"):
        match location.args:
            case ["~" | "~*" as operator, pattern]:
                flags = re.IGNORECASE if operator == "~*" else 0
                if re.search(pattern, uri, flags):
                    return location
    assert longest is not None, f"no location serves {uri}"
    return longest[1]


def effective(location: Directive, name: str) -> list[list[str]]:
    """Every ``name`` directive in force in ``location``: those of the innermost level that
    has any (nginx inherits a directive only into a level that sets none of its own)."""
    for level in (location, SERVER, HTTP):
        found = level.children(name)
        if found:
            return [directive.args for directive in found]
    return []


def single(location: Directive, name: str, default: str) -> str:
    found = effective(location, name)
    return found[-1][0] if found else default


def groups(pattern: str, text: str) -> tuple[str, ...]:
    """The groups of ``pattern`` matching the start of ``text`` (which it must)."""
    found = re.match(pattern, text)
    assert found is not None, f"{text!r} does not match {pattern!r}"
    return found.groups()


def seconds(value: str) -> float:
    number, unit = groups(r"(\d+)(ms|s|m|h|d)?$", value)
    return int(number) * {"ms": 0.001, "s": 1, "m": 60, "h": 3600, "d": 86400}[unit or "s"]


def size_bytes(value: str) -> int:
    number, unit = groups(r"(\d+)([kKmMgG])?$", value)
    return int(number) * {"k": 1024, "m": 1024**2, "g": 1024**3}.get((unit or "").lower(), 1)


def sample_uri(path: str) -> str:
    """A request path for a route path: every {parameter} filled in."""
    return re.sub(r"\{[^}]+\}", "Xk3_f9-2", path)


def route_path(router_module: ModuleType, ending: str) -> str:
    """The one path of the module's router that ends with ``ending``."""
    paths = [route.path for route in router_module.router.routes]
    (path,) = [p for p in paths if p.endswith(ending)]
    return path


EVENTS_URI = sample_uri(route_path(events, "/events"))
PHOTO_URI = sample_uri(route_path(photos, "/photo"))
HEALTH_PATH = route_path(health, "/healthz")
APP_URIS = ["/", "/join/482913", "/api/solve", PHOTO_URI, EVENTS_URI, HEALTH_PATH]


# --- compose: settings and database ---------------------------------------------------------


def test_compose_sets_only_real_settings_and_they_parse(monkeypatch: pytest.MonkeyPatch) -> None:
    """Settings ignore unknown variables, so a misspelt BUDDY_DATABASE_URI would leave every
    replica on a SQLite file of its own: phones on different replicas would never meet."""
    settings = {
        name: value for name, value in environment(BACKEND, {}).items() if name.startswith("BUDDY_")
    }
    assert "BUDDY_DATABASE_URL" in settings
    assert "BUDDY_PUBLIC_URL" in settings
    fields = {f"BUDDY_{name.upper()}" for name in Settings.model_fields}
    assert set(settings) <= fields, set(settings) - fields
    for name, value in settings.items():
        monkeypatch.setenv(name, value)
    parsed = Settings(_env_file=None)
    assert make_url(parsed.database_url).get_backend_name() == "postgresql"


@pytest.mark.parametrize("dotenv", [{}, {"POSTGRES_PASSWORD": "s3cretFromDotEnv"}])
def test_database_url_reaches_postgres_with_psycopg(dotenv: dict[str, str]) -> None:
    """The URL names the psycopg 3 driver (plain postgresql:// means psycopg2, which is not
    installed) and the postgres service with its user, database and password: also when
    .env sets the password, which both places must then take."""
    url = make_url(environment(BACKEND, dotenv)["BUDDY_DATABASE_URL"])
    database = environment(POSTGRES, dotenv)
    assert url.drivername == "postgresql+psycopg"
    assert url.host == "postgres"
    assert url.host in SERVICES
    assert url.port == 5432
    assert url.username == database["POSTGRES_USER"]
    assert url.database == database["POSTGRES_DB"]
    assert url.password == database["POSTGRES_PASSWORD"]
    assert url.password == dotenv.get("POSTGRES_PASSWORD", url.password)


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


def test_the_image_installs_everything_the_app_imports() -> None:
    """The image installs pyproject's runtime dependencies and nothing else (what was put
    into the development venv by hand does not count): every package the app's code imports
    when it starts, and the driver of the compose database URL with a libpq for it, must
    come from them, or each replica stops at start-up."""
    url = environment(BACKEND, {})["BUDDY_DATABASE_URL"]
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
    assert libpq or any("libpq" in args for args in RUNTIME.all("RUN"))


def test_postgres_is_ready_before_the_app_and_keeps_its_data() -> None:
    """The app migrates the database at start-up and gives up if it refuses, so it starts
    only once pg_isready answers (as the app's user: as "root" it logs a refusal
    every 5 s); the data lives in a named volume, not in a container that a rebuild drops."""
    check = POSTGRES["healthcheck"]["test"]
    assert "pg_isready" in check
    user = environment(POSTGRES, {})["POSTGRES_USER"]
    assert check[check.index("-U") + 1] == user
    assert BACKEND["depends_on"]["postgres"]["condition"] == "service_healthy"
    volumes = [str(volume).split(":") for volume in POSTGRES["volumes"]]
    assert ["pgdata", "/var/lib/postgresql/data"] in volumes
    assert "pgdata" in COMPOSE["volumes"]


# --- compose: replicas and ports ------------------------------------------------------------


def test_two_replicas_reachable_only_through_nginx() -> None:
    """Two replicas share the load; they publish no port (so only nginx can send the
    X-Forwarded-* headers they trust) and have no container_name (two containers cannot
    share one); nginx, with this repository's config, starts once they are healthy."""
    assert BACKEND["deploy"]["replicas"] == 2
    assert "ports" not in BACKEND
    assert "container_name" not in BACKEND
    assert [name for name, service in SERVICES.items() if service.get("ports")] == ["nginx"]
    assert NGINX["depends_on"]["backend"]["condition"] == "service_healthy"
    assert "./deploy/nginx.conf:/etc/nginx/nginx.conf:ro" in NGINX["volumes"]


def test_nginx_proxies_to_the_port_uvicorn_listens_on() -> None:
    """Every location passes to the upstream, whose servers are the backend service on the
    port of the image's CMD (and EXPOSE); its idle connections close before uvicorn's
    keep-alive does (5 s), or nginx sends requests into closing sockets: sporadic 502s."""
    (servers,) = [d.args for d in UPSTREAM.children("server")]
    assert servers[0] == f"backend:{APP_PORT}"
    assert "backend" in SERVICES
    assert RUNTIME.all("EXPOSE") == [str(APP_PORT)]
    for location in SERVER.children("location"):
        if not location.args[0].startswith("@"):
            assert location.children("proxy_pass")[0].args == [f"http://{UPSTREAM.args[0]}"]
    uvicorn_keepalive = 5.0
    if "--timeout-keep-alive" in uvicorn_command():
        uvicorn_keepalive = float(option(uvicorn_command(), "--timeout-keep-alive"))
    (timeout,) = UPSTREAM.children("keepalive_timeout")
    assert seconds(timeout.args[0]) < uvicorn_keepalive


def test_the_published_port_is_the_one_nginx_listens_on() -> None:
    """The host port (8080 unless .env sets HTTP_PORT) leads to nginx's listening port."""
    ((host, container),) = published_ports(NGINX)
    (listen,) = SERVER.children("listen")
    assert int(listen.args[0]) == container
    assert host == "8080"
    assert interpolate("${HTTP_PORT:-8080}", {"HTTP_PORT": "80"}) == "80"


# --- Dockerfile -----------------------------------------------------------------------------


def test_healthcheck_asks_healthz_on_the_app_port() -> None:
    """The image's health (which nginx waits for) is GET /healthz, a route of the app, on
    the port uvicorn listens on inside the container."""
    command = healthcheck_command()
    assert command[:2] == ["python", "-c"]
    (url,) = re.findall(r"https?://[^'\"]+", command[2])
    parts = urlsplit(url)
    assert parts.hostname in ("127.0.0.1", "localhost")
    assert parts.port == APP_PORT
    assert parts.path == HEALTH_PATH == "/healthz"


@pytest.fixture
def fake_app() -> Iterator[tuple[int, dict[str, int]]]:
    """A loopback server answering GET /healthz with the status in ``answer["status"]``."""
    answer = {"status": 200}

    class Health(BaseHTTPRequestHandler):
        def do_GET(self) -> None:
            self.send_response(answer["status"] if self.path == "/healthz" else 404)
            self.end_headers()

        def log_message(self, *args: object) -> None:
            pass

    server = HTTPServer(("127.0.0.1", 0), Health)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield server.server_address[1], answer
    server.shutdown()
    server.server_close()


def test_healthcheck_fails_when_the_database_does_not_answer(
    fake_app: tuple[int, dict[str, int]],
) -> None:
    """/healthz answers 503 when the database is gone: the check must then fail, or nginx
    keeps sending phones to a replica that can only refuse them."""
    port, answer = fake_app
    _, flag, code = healthcheck_command()
    code = code.replace(f":{APP_PORT}/", f":{port}/")
    for status, healthy in ((200, True), (503, False)):
        answer["status"] = status
        command = [sys.executable, flag, code]
        run = subprocess.run(command, check=False, capture_output=True, timeout=20)
        assert (run.returncode == 0) == healthy, (status, run.stderr.decode())


def test_dockerfile_builds_the_phone_app_with_node() -> None:
    """A Node stage (a version package.json accepts) runs `npm ci` from the lock file and
    `npm run build`; the runtime copies its dist/ to where the app looks by default
    (BUDDY_FRONTEND_DIR, relative to the app's folder), or / answers "not built yet"."""
    node = STAGES[0]
    engines = json.loads((ROOT / "frontend" / "package.json").read_text())["engines"]["node"]
    (node_major,) = groups(r"node:(\d+)", node.image)
    (least_major,) = groups(r">=\s*(\d+)", engines)
    assert int(node_major) >= int(least_major), (node.image, engines)
    steps = [f"{key} {args}" for key, args in node.instructions]
    lock = next(i for i, step in enumerate(steps) if "package-lock.json" in step)
    npm_ci = next(i for i, step in enumerate(steps) if step.startswith("RUN npm ci"))
    build = next(i for i, step in enumerate(steps) if step.startswith("RUN npm run build"))
    assert lock < npm_ci < build
    (workdir,) = node.all("WORKDIR")
    copies = [args.split() for args in RUNTIME.all("COPY") if args.startswith("--from=")]
    assert [f"--from={node.name}", f"{workdir}/dist"] in [copy[:2] for copy in copies]
    (destination,) = [copy[2] for copy in copies if copy[1] == f"{workdir}/dist"]
    (app_dir,) = RUNTIME.all("WORKDIR")
    assert Path(app_dir, destination) == Path(app_dir, DEFAULTS["frontend_dir"])


def test_runtime_is_slim_python_311_with_the_app_and_without_test_packages() -> None:
    """The final image is python:3.11-slim, installs pyproject's runtime dependencies (not
    the test extras: pytest, mypy, Playwright) and copies every package of the project (a
    new top-level package left out would be an ImportError at start-up)."""
    assert RUNTIME.image.startswith("python:3.11-slim")
    installs = [args for args in RUNTIME.all("RUN") if "pip install" in args]
    assert installs
    assert not any("[test]" in args or ".[" in args for args in installs)
    assert any("['dependencies']" in args or "requirements" in args for args in installs)
    copied = {args.split()[0].rstrip("/") for args in RUNTIME.all("COPY")}
    setuptools = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    for pattern in setuptools["packages"]["find"]["include"]:
        assert pattern.rstrip("*") in copied, pattern


def test_runtime_runs_uvicorn_as_a_user_behind_the_proxy() -> None:
    """Not root; uvicorn serves backend.main:app on all interfaces, takes the client's
    address and https from nginx's headers (from any address: nginx is on another
    container), keeps no access log (tokens in URLs) and stops in seconds though event
    streams never end."""
    users = RUNTIME.all("USER")
    assert users
    assert users[-1].split(":")[0] not in ("root", "0")
    command = uvicorn_command()
    assert command[:2] == ["uvicorn", "backend.main:app"]
    assert option(command, "--host") == "0.0.0.0"
    assert "--proxy-headers" in command
    assert option(command, "--forwarded-allow-ips") == "*"
    assert "--no-access-log" in command
    assert float(option(command, "--timeout-graceful-shutdown")) <= 5


# --- .dockerignore --------------------------------------------------------------------------


def dockerignored(path: str) -> bool:
    """Whether .dockerignore keeps ``path`` out of the build context: the last pattern that
    matches the path or one of its folders decides; ``!`` lets it back in."""
    ignored = False
    for line in (ROOT / ".dockerignore").read_text().splitlines():
        pattern = line.strip()
        if not pattern or pattern.startswith("#"):
            continue
        keep = pattern.startswith("!")
        glob = re.escape(pattern.lstrip("!").strip("/"))
        regex = glob.replace(r"\*\*/", "(?:.*/)?").replace(r"\*\*", ".*").replace(r"\*", "[^/]*")
        parts = path.split("/")
        if any(re.fullmatch(regex, "/".join(parts[:n])) for n in range(1, len(parts) + 1)):
            ignored = not keep
    return ignored


def test_dockerignore_keeps_secrets_out_and_the_sources_in() -> None:
    """.env (the database password) never enters an image; the host's node_modules and
    .venv stay out (big, and built for the host); every file the Dockerfile copies is in."""
    for private in (".env", ".venv/bin/python", "frontend/node_modules/vite/package.json"):
        assert dockerignored(private), private
    for local in ("var/buddy.db", "artifacts/x.png", "frontend/dist/index.html"):
        assert dockerignored(local), local
    copies = [args.split() for stage in STAGES for args in stage.all("COPY")]
    from_context = [copy[:-1] for copy in copies if not copy[0].startswith("--from=")]
    sources = [source.rstrip("/") for copy in from_context for source in copy]
    tracked = subprocess.run(
        ["git", "ls-files", *sources], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout.split()
    assert len(tracked) > 20
    assert [path for path in tracked if dockerignored(path)] == []


# --- deploy/nginx.conf ----------------------------------------------------------------------


def test_event_streams_are_neither_buffered_nor_cut() -> None:
    """The app's event stream path lands in a location that passes each event on at once
    (with buffering, a phone would see "your buddy joined" minutes late) and waits far
    longer than the ping interval before it calls an idle stream dead."""
    location = location_for(EVENTS_URI)
    assert single(location, "proxy_buffering", "on") == "off"
    timeout = seconds(single(location, "proxy_read_timeout", "60s"))
    assert timeout >= 10 * DEFAULTS["keepalive_seconds"]
    assert timeout >= 3600
    # ...and not every request: a hung upload or solve still ends after nginx's default.
    assert seconds(single(location_for(PHOTO_URI), "proxy_read_timeout", "60s")) <= 300


@pytest.mark.parametrize("uri", APP_URIS)
def test_every_request_reaches_the_app_with_the_phones_host_and_scheme(uri: str) -> None:
    """HTTP/1.1 with an empty Connection header (upstream keep-alive, streaming), the Host
    with the port the phone used (join links point back to it) and X-Forwarded-For/Proto
    for uvicorn --proxy-headers, in every location: a location that set one header of its
    own would silently drop all the others (nginx's inheritance)."""
    location = location_for(uri)
    assert single(location, "proxy_http_version", "1.0") == "1.1"
    headers = {args[0].lower(): args[1] for args in effective(location, "proxy_set_header")}
    assert headers.get("connection") == ""
    assert headers.get("host") == "$http_host"
    # The address nginx sees, not appended to one the client sent: uvicorn (trusting every
    # hop, --forwarded-allow-ips *) would take the client's, and a guesser of join codes
    # could name a fresh address with each request.
    assert headers.get("x-forwarded-for") == "$remote_addr"
    assert headers.get("x-forwarded-proto") == "$scheme"


def test_nginx_lets_through_every_body_the_app_accepts() -> None:
    """nginx's default is 1 MB: every photo would get nginx's 413 instead of reaching the
    app, which accepts up to BUDDY_MAX_BODY_BYTES."""
    limit = single(location_for(PHOTO_URI), "client_max_body_size", "1m")
    assert size_bytes(limit) >= DEFAULTS["max_body_bytes"]


def test_nginx_refusals_have_the_apps_error_shape() -> None:
    """When nginx answers instead of the app (body too large, no replica up), the phone
    app still gets {"error": {"code", "message"}} and shows the message."""
    handled = {code for args in effective(SERVER, "error_page") for code in args[:-1]}
    assert {"413", "502", "503", "504"} <= handled
    for location in SERVER.children("location"):
        if location.args[0].startswith("@"):
            (answer,) = location.children("return")
            body = json.loads(answer.args[1])
            assert set(body) == {"error"}
            assert isinstance(body["error"]["code"], str)
            assert body["error"]["message"].endswith(".")
            assert location.children("default_type")[0].args == ["application/json"]
