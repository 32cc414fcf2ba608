"""``python -m backend`` (what ``make run`` runs): serve the app for phones on this network."""

from __future__ import annotations

import socket

import uvicorn

from backend.settings import get_settings


def lan_address() -> str | None:
    """This machine's address on the local network (no packet is sent), if it has one."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        try:
            probe.connect(("10.255.255.255", 1))
            address = str(probe.getsockname()[0])
        except OSError:
            return None
    return None if address.startswith("127.") else address


def main() -> None:
    settings = get_settings()
    port = settings.port
    print("Buddy Search is running. Stop it with Ctrl+C.")
    print(f"  on this computer:  http://127.0.0.1:{port}")
    if settings.host in ("0.0.0.0", "::") and (address := lan_address()):
        print(f"  on the phones:     http://{address}:{port}  (same Wi-Fi)")
    print(f"  API docs:          http://127.0.0.1:{port}/docs")
    print(f"  data:              {settings.database_url}")
    print(f"  processes:         {settings.workers}", flush=True)
    # No access log: event streams and pictures carry the session token in their URL.
    uvicorn.run(
        "backend.main:app",
        host=settings.host,
        port=port,
        access_log=False,
        proxy_headers=True,
        # Event streams never end by themselves: do not wait for them on Ctrl+C or SIGTERM.
        timeout_graceful_shutdown=3,
        log_level="info",
        workers=settings.workers,
    )


if __name__ == "__main__":
    main()
