"""The phone app is served at /, and its own routes load it after a reload."""

from __future__ import annotations

from pathlib import Path

from fastapi.testclient import TestClient

from backend.main import create_app
from backend.settings import Settings


def app_client(tmp_path: Path, database_url: str, built: bool) -> TestClient:
    dist = tmp_path / "dist"
    if built:
        (dist / "assets").mkdir(parents=True)
        (dist / "index.html").write_text("<!doctype html><title>Buddy Search</title><div id=app>")
        (dist / "assets" / "app.js").write_text("console.log('buddy')")
        (dist / "icon.svg").write_text("<svg/>")
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
        assert client.get("/../pyproject.toml").status_code in (200, 404)
        assert "pyproject" not in client.get("/%2e%2e/pyproject.toml").text
        # The API keeps its own answers.
        unknown = client.get("/api/nowhere")
        assert unknown.status_code == 404
        assert unknown.json()["error"]["code"] == "not_found"
        assert client.get("/healthz").json() == {"status": "ok"}


def test_an_unbuilt_app_says_how_to_build_it(tmp_path: Path, database_url: str) -> None:
    with app_client(tmp_path, database_url, built=False) as client:
        page = client.get("/")
        assert page.status_code == 200
        assert "make run" in page.text
