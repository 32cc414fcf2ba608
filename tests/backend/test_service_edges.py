"""The service's edges: unknown routes, wrong methods, big bodies, health, docs; the phone app
served at /, its own routes loading it after a reload."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

from fastapi.testclient import TestClient
from phones import error_of

from backend.main import create_app
from backend.settings import Settings
from testbed.client import server_timing


def test_unknown_routes_and_methods_answer_in_the_one_shape(client: TestClient) -> None:
    missing = client.get("/api/nowhere")
    assert error_of(missing, 404) == "not_found"
    wrong = client.delete("/api/solve")
    assert error_of(wrong, 405) == "method_not_allowed"
    assert wrong.headers["Allow"] == "POST"


def test_bodies_over_the_limit_are_refused(settings: Settings) -> None:
    limited = settings.model_copy(update={"max_body_bytes": 1000})
    with TestClient(create_app(limited)) as client:
        declared = client.post(
            "/api/solve", content=b"x" * 2000, headers={"Content-Type": "application/json"}
        )
        assert error_of(declared, 413) == "body_too_large"

        def chunks() -> Iterator[bytes]:  # no Content-Length: counted while reading
            for _ in range(5):
                yield b"x" * 500

        streamed = client.post(
            "/api/solve", content=chunks(), headers={"Content-Type": "application/json"}
        )
        assert error_of(streamed, 413) == "body_too_large"
        assert client.get("/healthz").status_code == 200  # still serving


def test_health_and_version(client: TestClient) -> None:
    assert client.get("/healthz").json() == {"status": "ok"}
    version = client.get("/api/version")
    assert version.json()["version"]
    # Every answer says how long the server spent on it, and in database statements.
    assert version.headers["server-timing"].startswith("app;dur=")
    parts = server_timing(version.headers["server-timing"])
    assert set(parts) == {"app", "db"}
    assert parts["app"] >= 0
    assert parts["db"] == 0.0  # the version reads no database


def test_the_server_timing_counts_the_database_statements_of_the_call_it_answers(
    client: TestClient,
) -> None:
    """The statements run in the route's worker thread, whose tally is the request's."""
    created = client.post("/api/sessions")
    assert created.status_code == 201, created.text
    parts = server_timing(created.headers["server-timing"])
    assert 0 < parts["db"] <= parts["app"]
    # The next call starts its own tally: another version's reads none.
    assert server_timing(client.get("/api/version").headers["server-timing"])["db"] == 0.0


def test_docs_are_served_without_the_internet(client: TestClient) -> None:
    page = client.get("/docs")
    assert page.status_code == 200
    assert "cdn." not in page.text
    assert "http://" not in page.text.replace("http://testserver", "")
    assert "https://" not in page.text
    for asset in ("/docs-assets/swagger-ui-bundle.js", "/docs-assets/swagger-ui.css"):
        assert client.get(asset).status_code == 200


def test_every_endpoint_is_documented_with_examples(client: TestClient) -> None:
    """Each operation: a description, an example of its request body (if it takes one) and
    of its successful answer (pictures excepted), and of its refusals."""
    spec = client.get("/openapi.json").json()
    schemas = spec["components"]["schemas"]

    def has_example(node: object, seen: frozenset[str] = frozenset()) -> bool:
        if isinstance(node, dict):
            if "example" in node or "examples" in node:
                return True
            reference = node.get("$ref")
            if isinstance(reference, str):
                name = reference.rsplit("/", 1)[-1]
                return name not in seen and has_example(schemas[name], seen | {name})
            return any(has_example(value, seen) for value in node.values())
        return isinstance(node, list) and any(has_example(value, seen) for value in node)

    for path, operations in spec["paths"].items():
        for method, operation in operations.items():
            where = f"{method.upper()} {path}"
            assert operation.get("description"), where
            body = operation.get("requestBody", {}).get("content", {})
            if "application/json" in body:
                assert has_example(body["application/json"]), where
            for form in body.get("multipart/form-data", {}).values():  # files: no example
                name = form["$ref"].rsplit("/", 1)[-1]
                for field, part in schemas[name]["properties"].items():
                    file = part.get("format") == "binary" or "contentMediaType" in part
                    assert file or has_example(part), (where, field)
            success = {k: v for k, v in operation["responses"].items() if k.startswith("2")}
            pictures = all(
                set(answer.get("content", {})) <= {"image/png", "image/jpeg"}
                for answer in success.values()
            )
            if not pictures and any("content" in answer for answer in success.values()):
                assert has_example(success), where
            refusals = {k: v for k, v in operation["responses"].items() if k[0] in "45"}
            assert all(has_example(answer) for answer in refusals.values()), where


def app_client(tmp_path: Path, database_url: str, built: bool) -> TestClient:
    dist = tmp_path / "dist"
    if built:
        (dist / "assets").mkdir(parents=True)
        (dist / "index.html").write_text("<!doctype html><title>Buddy Search</title><div id=app>")
        (dist / "assets" / "app.js").write_text("console.log('buddy')")
        (dist / "icon.svg").write_text("<svg/>")
        (dist / "sw.js").write_text("self.addEventListener('fetch', () => {})")
        (dist / "manifest.webmanifest").write_text('{"name": "Buddy Search"}')
    settings = Settings(database_url=database_url, frontend_dir=str(dist))
    return TestClient(create_app(settings))


def test_the_app_and_its_routes_are_served(tmp_path: Path, database_url: str) -> None:
    with app_client(tmp_path, database_url, built=True) as client:
        for path in ("/", "/join/482913", "/s"):
            page = client.get(path)
            assert page.status_code == 200
            assert "Buddy Search" in page.text
        assert client.get("/assets/app.js").text == "console.log('buddy')"
        assert client.get("/icon.svg").status_code == 200
        # The service worker and the manifest: always asked for again, in their own types.
        for path, media_type in (
            ("/sw.js", "text/javascript"),
            ("/manifest.webmanifest", "application/manifest+json"),
            ("/", "text/html"),
        ):
            answer = client.get(path)
            assert answer.headers["cache-control"] == "no-cache", path
            assert answer.headers["content-type"].startswith(media_type), path
        assert client.get("/../pyproject.toml").status_code in (200, 404)
        assert "pyproject" not in client.get("/%2e%2e/pyproject.toml").text
        # The API keeps its own answers.
        unknown = client.get("/api/nowhere")
        assert error_of(unknown, 404) == "not_found"
        assert client.get("/healthz").json() == {"status": "ok"}


def test_an_unbuilt_app_says_how_to_build_it(tmp_path: Path, database_url: str) -> None:
    with app_client(tmp_path, database_url, built=False) as client:
        page = client.get("/")
        assert page.status_code == 200
        assert "make run" in page.text
