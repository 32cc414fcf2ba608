"""A phone's path to the server with the venue's round trip in it: a loopback TCP proxy
that delays every byte by half the round trip each way, and the first bytes of each new
connection by one more round trip (TCP's handshake).

Chromium's own emulation (``Network.emulateNetworkConditions``) adds its ``latency`` to a
request's response only: the request itself reaches the server at once, and the chunks of an
open event stream arrive without delay (measured on loopback: a PUT arrived 3-10 ms after
``fetch``, an event 0-8 ms after the server sent it, with 300 ms of latency set). A tap that
goes up and an answer that comes down an open stream would then cost no round trip at all.
Here the delay is where a network puts it, on each direction of every connection; Chromium
still limits the throughput (``meter.py``).
"""

from __future__ import annotations

import asyncio
import threading
import time
from contextlib import suppress

CHUNK = 64 * 1024


class Link:
    """127.0.0.1:``port`` forwarding to 127.0.0.1:``upstream``, ``round_trip_ms`` away,
    running for a ``with`` block."""

    def __init__(self, upstream: int, round_trip_ms: float) -> None:
        self.upstream = upstream
        self.one_way = round_trip_ms / 2000.0
        self.port = 0
        self._loop = asyncio.new_event_loop()
        self._stop = asyncio.Event()
        self._ready = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)

    @property
    def base_url(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    def __enter__(self) -> Link:
        self._thread.start()
        self._ready.wait(10)
        return self

    def __exit__(self, *_: object) -> None:
        self._loop.call_soon_threadsafe(self._stop.set)
        self._thread.join(10)

    def _run(self) -> None:
        # The runner, once serving ends, cancels the connections still open and closes the loop.
        with asyncio.Runner(loop_factory=lambda: self._loop) as runner:
            runner.run(self._serve())

    async def _serve(self) -> None:
        server = await asyncio.start_server(self._connected, "127.0.0.1", 0)
        self.port = server.sockets[0].getsockname()[1]
        self._ready.set()
        await self._stop.wait()
        server.close()

    async def _connected(self, phone: asyncio.StreamReader, to_phone: asyncio.StreamWriter) -> None:
        # The handshake: the phone's first bytes leave a round trip after it connected.
        opened = time.monotonic() + 2 * self.one_way
        try:
            server, to_server = await asyncio.open_connection("127.0.0.1", self.upstream)
        except OSError:
            to_phone.close()
            return
        await asyncio.gather(
            self._carry(phone, to_server, opened),
            self._carry(server, to_phone, 0.0),
            return_exceptions=True,
        )
        for writer in (to_phone, to_server):
            writer.close()

    async def _carry(
        self, source: asyncio.StreamReader, sink: asyncio.StreamWriter, not_before: float
    ) -> None:
        """Every chunk of ``source`` on to ``sink`` half a round trip after it came, in
        order (and not before ``not_before``); then the end of the stream."""
        queue: asyncio.Queue[tuple[float, bytes]] = asyncio.Queue()

        async def deliver() -> None:
            while True:
                due, data = await queue.get()
                await asyncio.sleep(max(0.0, due - time.monotonic()))
                if not data:
                    with suppress(OSError):
                        sink.write_eof()
                    return
                sink.write(data)
                await sink.drain()

        delivering = asyncio.ensure_future(deliver())
        try:
            while True:
                data = await source.read(CHUNK)
                queue.put_nowait((max(time.monotonic() + self.one_way, not_before), data))
                if not data:
                    break
            await delivering
        except (OSError, asyncio.CancelledError):
            delivering.cancel()
            raise
