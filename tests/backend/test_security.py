"""Guessing join codes, tokens, the headers every answer carries, and no CORS.

The guessing limits are counted in the database: every test runs on SQLite and PostgreSQL,
and one runs two apps (two replicas) on the same database.
"""

from __future__ import annotations

import base64
import hashlib
import re
from pathlib import Path

import httpx2
import pytest
from fastapi import FastAPI
from fastapi.testclient import TestClient
from phones import FakeClock, error_of, joined

from backend.main import create_app
from backend.pairing import guessing
from backend.pairing.guessing import client_key
from backend.security import APP_POLICY
from backend.settings import Settings
from backend.wiring import Services
from deploy.replica import serve
from testbed.client import Phone, start

PER_CLIENT = 5
OVERALL = 12


@pytest.fixture
def settings(settings: Settings) -> Settings:
    """Small limits, to reach them in a few requests."""
    limits = {"join_failures_per_client": PER_CLIENT, "join_failures_overall": OVERALL}
    return settings.model_copy(update=limits)


def from_address(app: FastAPI, address: str) -> TestClient:
    """Another phone on the same running app, from ``address``."""
    return TestClient(app, raise_server_exceptions=False, client=(address, 40000))


def wrong_code(*right: str) -> str:
    """A code that names no session's search (the codes in play are few, and all known)."""
    numbers = {code[:4] for code in right}
    return next(f"{n:04d}0000" for n in range(10_000) if f"{n:04d}" not in numbers)


def join(client: TestClient, code: str) -> httpx2.Response:
    return client.post("/api/sessions/join", json={"code": code})


# --- guessing join codes --------------------------------------------------------------


def test_an_address_that_keeps_guessing_is_stopped_even_with_the_right_code(
    client: TestClient, clock: FakeClock
) -> None:
    wrong = wrong_code()
    for _ in range(PER_CLIENT):
        assert error_of(join(client, wrong)) == "invalid_join_code"
        clock.advance(10)
    code = start(client)[1]
    refused = join(client, code)  # right, but from an address that has guessed enough
    assert error_of(refused, 429) == "too_many_attempts"
    assert "try again in 9 minutes" in refused.json()["error"]["message"]
    # Until the first failure, 50 s ago, leaves the 10-minute window.
    assert refused.headers["Retry-After"] == str(600 - 50)
    clock.advance(549)
    assert join(client, code).status_code == 429
    clock.advance(1)
    joined = join(client, code)
    assert joined.status_code == 200, joined.text
    # One failure left the window: one more may be made, then it waits again.
    assert error_of(join(client, wrong)) == "invalid_join_code"
    assert join(client, wrong).status_code == 429


def test_right_codes_never_count_so_a_crowd_behind_one_address_joins(
    client: TestClient,
) -> None:
    """A stadium behind one carrier address: many joiners joining, a few typos."""
    codes = [start(client)[1] for _ in range(3 * PER_CLIENT)]
    for n, code in enumerate(codes):
        if n % 4 == 0:  # a typo now and then, under the limit
            assert error_of(join(client, wrong_code(*codes))) == "invalid_join_code"
        assert join(client, code).status_code == 200


def test_a_used_or_expired_code_counts_as_a_failure(client: TestClient, clock: FakeClock) -> None:
    used = start(client)[1]
    assert join(client, used).status_code == 200
    expired = start(client)[1]
    clock.advance(601)
    replayed = [join(client, code).status_code for code in [used, expired] * PER_CLIENT]
    assert replayed[: PER_CLIENT + 1] == [404] * PER_CLIENT + [429]


def same_search(code: str, n: int) -> str:
    """A wrong code with ``code``'s search number (its first four digits)."""
    return code[:4] + f"{(int(code[4:]) + 1 + n) % 10_000:04d}"


def test_a_code_is_renewed_after_five_wrong_codes_name_its_search(
    client: TestClient, app: FastAPI
) -> None:
    """A guesser who knows (or hit) a search's number gets five tries at its secret, from
    however many addresses: then the code is a new one, shown on the starter's phone."""
    starter, code = start(client)
    for n in range(5):  # each from its own address: no address reaches its own limit
        guesser = from_address(app, f"198.51.100.{n}")
        assert error_of(join(guesser, same_search(code, n))) == "invalid_join_code"
    assert error_of(join(from_address(app, "192.0.2.1"), code)) == "invalid_join_code"
    state = starter.state()
    renewed = state["join_code"]
    assert re.fullmatch(r"[0-9]{8}", renewed)
    assert renewed != code
    assert state["join_code_renewals"] == 1
    assert state["join_url"].endswith(f"/join/{renewed}")
    assert state["version"] == 2  # a change the phone is told of, with its own event
    log = client.app.state.services.streams.log  # type: ignore[attr-defined]
    assert [e.type for e in log.events_after(starter.session_id, 0)] == ["code"]
    joined = join(from_address(app, "192.0.2.2"), renewed)
    assert joined.status_code == 200, joined.text


def test_a_renewal_that_draws_only_taken_codes_ends_the_code(
    client: TestClient, app: FastAPI, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Never two sessions with one code: if every code drawn is taken (impossible but for
    a broken generator), the code ends, and the starter's phone offers a new search."""
    taken = start(client)[1]
    starter, code = start(client)
    monkeypatch.setattr(guessing, "new_join_code", lambda: taken)
    for n in range(5):
        join(from_address(app, f"198.51.100.{n}"), same_search(code, n))
    state = starter.state()
    assert (state["join_code"], state["join_code_renewals"]) == (None, 1)
    assert join(client, taken).status_code == 200  # still the other session's


@pytest.mark.parametrize("typos", [True, False], ids=["four-typos", "six-of-other-searches"])
def test_wrong_codes_leave_the_code_as_it_is(client: TestClient, app: FastAPI, typos: bool) -> None:
    """A joiner's typos (four, in the secret) do not cost them the code; nor do wrong codes
    of other searches (six), which do not count against it."""
    starter, code = start(client)
    for n in range(4 if typos else 6):
        wrong = same_search(code, n) if typos else wrong_code(code)
        assert join(from_address(app, f"198.51.100.{n}"), wrong).status_code == 404
    state = starter.state()
    assert (state["join_code"], state["join_code_renewals"]) == (code, 0)
    assert join(client, code).status_code == 200


def test_the_joiner_never_sees_the_code_or_its_renewals(client: TestClient, app: FastAPI) -> None:
    starter, code = start(client)
    for n in range(5):
        join(from_address(app, f"198.51.100.{n}"), same_search(code, n))
    state = joined(client, starter.state()["join_code"]).state()
    assert (state["join_code"], state["join_code_renewals"]) == (None, 0)


def test_each_address_has_its_own_limit_and_ipv6_counts_by_64(
    client: TestClient, app: FastAPI
) -> None:
    code = start(client)[1]
    wrong = wrong_code(code)
    guesser = from_address(app, "2001:db8:1:2::17")
    for _ in range(PER_CLIENT):
        assert join(guesser, wrong).status_code == 404
    assert join(guesser, code).status_code == 429
    # Another address of the same /64 is the same subscriber.
    assert join(from_address(app, "2001:db8:1:2:ffff:ffff:ffff:1"), code).status_code == 429
    # Another subscriber is not held back.
    assert join(from_address(app, "2001:db8:1:3::17"), code).status_code == 200


def test_client_addresses_are_counted_as_subscribers() -> None:
    assert client_key("203.0.113.9") == "203.0.113.9"
    assert client_key("2001:db8:1:2:3:4:5:6") == "2001:db8:1:2::/64"
    assert client_key("::ffff:203.0.113.9") == "203.0.113.9"
    assert client_key("testclient") == "testclient"
    assert client_key("") == "unknown"


def test_guessing_from_many_addresses_leaves_one_guess_each(
    client: TestClient, app: FastAPI
) -> None:
    """Above the overall limit an address that has failed waits; a fresh one (a joiner
    typing a code for the first time) may still try."""
    code = start(client)[1]
    wrong = wrong_code(code)
    guessers = [from_address(app, f"198.51.100.{n}") for n in range(OVERALL // PER_CLIENT + 1)]
    failures = 0
    for guesser in guessers:
        while failures < OVERALL and join(guesser, wrong).status_code == 404:
            failures += 1
    assert failures == OVERALL
    # Each guesser has failed; the ones under their own limit are now held back too.
    last = guessers[-1]
    refused = join(last, code)
    assert refused.status_code == 429
    assert "being tried" in refused.json()["error"]["message"]
    # A fresh address has one try: a typo, then it waits...
    typo = from_address(app, "192.0.2.10")
    assert join(typo, wrong).status_code == 404
    assert join(typo, code).status_code == 429
    # ...and one that types the code right joins.
    assert join(from_address(app, "192.0.2.11"), code).status_code == 200


def test_replicas_share_the_count(client: TestClient, settings: Settings, clock: FakeClock) -> None:
    code = start(client)[1]
    wrong = wrong_code(code)
    for _ in range(PER_CLIENT):
        assert join(client, wrong).status_code == 404
    with TestClient(create_app(settings, clock), raise_server_exceptions=False) as other:
        assert join(other, code).status_code == 429


def test_failures_are_forgotten_after_the_window(
    client: TestClient, clock: FakeClock, services: Services
) -> None:
    """The addresses of failed joins are not kept longer than they count."""
    wrong = wrong_code()
    for _ in range(3):
        join(client, wrong)
    engine = services.database.engine

    def kept() -> int:
        with engine.connect() as connection:
            return int(
                connection.exec_driver_sql("SELECT COUNT(*) FROM join_failures").scalar_one()
            )

    services.pairing.sweep()
    assert kept() == 3
    clock.advance(600)
    services.pairing.sweep()
    assert kept() == 0


def test_a_proxys_forwarded_address_is_the_one_counted(tmp_path: Path) -> None:
    """Through a trusted proxy (here: loopback, uvicorn's default) the address counted is
    the one the proxy forwards, not the proxy's own: else one guesser would stop everyone
    behind the proxy, and could not be told apart."""
    env = {"BUDDY_JOIN_FAILURES_PER_CLIENT": "2"}
    with serve(tmp_path, env) as server, httpx2.Client(base_url=server.base_url) as http:
        code = http.post("/api/sessions").json()["join_code"]
        wrong = wrong_code(code)

        def join_from(address: str, join_code: str) -> int:
            answer = http.post(
                "/api/sessions/join",
                json={"code": join_code},
                headers={"X-Forwarded-For": address},
            )
            return answer.status_code

        assert [join_from("203.0.113.5", wrong) for _ in range(3)] == [404, 404, 429]
        assert join_from("203.0.113.6", code) == 200


# --- tokens ---------------------------------------------------------------------------


def test_tokens_are_256_random_bits(client: TestClient) -> None:
    tokens = {client.post("/api/sessions").json()["token"] for _ in range(20)}
    assert len(tokens) == 20
    for token in tokens:
        assert re.fullmatch(r"[A-Za-z0-9_-]{43}", token)
        assert len(base64.urlsafe_b64decode(token + "=")) == 32


def test_only_the_exact_token_opens_a_session(client: TestClient, starter: Phone) -> None:
    """A token one character off, a prefix of it, or the hash the database keeps opens
    nothing: the token itself is the only key (compared as a whole, by its hash)."""
    assert starter.call("GET").status_code == 200
    token = starter.token
    flip = dict(zip("Aa0_-", "Bb1-_", strict=True))
    near_misses = [
        token[:i] + flip.get(token[i], "A") + token[i + 1 :]
        for i in (0, len(token) // 2, len(token) - 1)
    ]
    stored = hashlib.sha256(token.encode()).hexdigest()
    for wrong in [*near_misses, token[:-1], token + "A", stored, token.upper()]:
        if wrong == token:
            continue
        answer = client.get(starter.url(), headers={"Authorization": f"Bearer {wrong}"})
        assert error_of(answer, 401) == "unauthorized", wrong


# --- headers --------------------------------------------------------------------------

EVERYWHERE = {
    "x-content-type-options": "nosniff",
    "referrer-policy": "no-referrer",
    "x-frame-options": "DENY",
    "permissions-policy": "camera=(self), geolocation=(), microphone=()",
    "cross-origin-opener-policy": "same-origin",
    "cross-origin-resource-policy": "same-origin",
}


@pytest.mark.parametrize(
    ("path", "status"),
    [
        ("/", 200),
        ("/join/48291375", 200),
        ("/api/version", 200),
        ("/healthz", 200),
        ("/api/sessions/nope", 401),
        ("/api/nothing", 404),
        ("/openapi.json", 200),
    ],
)
def test_every_answer_carries_the_security_headers(
    client: TestClient, path: str, status: int
) -> None:
    answer = client.get(path)
    assert answer.status_code == status
    for name, value in EVERYWHERE.items():
        assert answer.headers.get(name) == value, name
    assert answer.headers["content-security-policy"] == APP_POLICY
    assert "strict-transport-security" not in answer.headers  # plain HTTP
    if path.startswith("/api/"):
        assert answer.headers["cache-control"] == "no-store"


def test_an_unexpected_error_carries_them_too(
    services: Services, starter: Phone, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A 500 is answered by Starlette's outermost middleware, outside the others."""

    def bug(*_: object) -> None:
        raise RuntimeError("a bug")

    monkeypatch.setattr(services.state, "state", bug)
    answer = starter.call("GET")
    assert error_of(answer, 500) == "internal_error"
    for name, value in EVERYWHERE.items():
        assert answer.headers.get(name) == value, name
    assert answer.headers["cache-control"] == "no-store"


def test_the_app_policy_allows_only_the_apps_own_files() -> None:
    directives = dict(part.split(" ", 1) for part in APP_POLICY.split("; "))
    assert directives["script-src"] == "'self'"
    assert directives["style-src"] == "'self'"
    assert directives["connect-src"] == "'self'"
    assert directives["worker-src"] == directives["manifest-src"] == "'self'"
    assert directives["frame-ancestors"] == "'none'"
    assert directives["object-src"] == "'none'"
    assert "unsafe" not in APP_POLICY


def test_state_and_pictures_are_not_kept_by_caches(
    client: TestClient, starter: Phone, joiner: Phone, temple_photos: tuple[bytes, bytes]
) -> None:
    """The state holds the join code: no cache keeps it. Pictures may stay in the phone's
    own cache, never in a shared one."""
    assert starter.call("GET").headers["cache-control"] == "no-store"
    assert joiner.upload(temple_photos[1], "photo.png").status_code == 200
    picture = client.get(starter.url("/photo/joiner"), params={"token": starter.token})
    assert picture.headers["cache-control"] == "private"


def test_https_answers_say_to_stay_on_https(app: FastAPI) -> None:
    """Directly over HTTPS, or through a trusted proxy's X-Forwarded-Proto (uvicorn's
    --proxy-headers turns that into the request's scheme)."""
    with TestClient(app, base_url="https://joiner.example") as secure:
        answer = secure.get("/api/version")
    assert answer.headers["strict-transport-security"] == "max-age=31536000"


def test_the_docs_allow_their_one_inline_script_by_its_hash(client: TestClient) -> None:
    page = client.get("/docs")
    assert page.status_code == 200
    policy = page.headers["content-security-policy"]
    scripts = re.findall(r"<script>(.*?)</script>", page.text, re.S)
    assert len(scripts) == 1
    digest = base64.b64encode(hashlib.sha256(scripts[0].encode()).digest()).decode()
    script_src = re.search(r"script-src ([^;]*)", policy)
    assert script_src is not None
    assert script_src.group(1).split() == ["'self'", f"'sha256-{digest}'"]
    assert "frame-ancestors 'none'" in policy
    assert "validator.swagger.io" not in page.text
    # Every other answer keeps the strict policy.
    style = client.get("/docs-assets/swagger-ui.css")
    assert style.headers["content-security-policy"] == APP_POLICY


# --- CORS -----------------------------------------------------------------------------


@pytest.mark.parametrize("method", ["POST", "GET", "PUT", "DELETE"])
def test_no_other_origin_is_let_in(client: TestClient, starter: Phone, method: str) -> None:
    origin = {"Origin": "https://evil.example"}
    preflight = client.options(
        starter.url(),
        headers={
            **origin,
            "Access-Control-Request-Method": method,
            "Access-Control-Request-Headers": "authorization, content-type",
        },
    )
    assert preflight.status_code >= 400
    simple = client.post("/api/sessions", headers=origin)
    assert simple.status_code == 201  # a browser would not let the other origin read it:
    state = client.get(starter.url(), headers={**origin, **starter.auth})
    for answer in (preflight, simple, state):
        assert not any(name.startswith("access-control-") for name in answer.headers)
