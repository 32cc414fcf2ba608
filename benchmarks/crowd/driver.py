"""The driver: plays both phones of every session, step by step, with people's pauses."""

from __future__ import annotations

import asyncio
import ssl
import time
from collections.abc import Callable
from typing import Any

import httpx2
import numpy as np

from testbed.scenes import Scene

from .people import LANDMARKS, PAUSES, SessionTaps, session_taps
from .phone import Phone, http_client
from .recorder import CREATE, CROP, DELETE, JOIN, OVERLAY, PHOTO, STORED, Recorder

EXPECTED_EVENTS = ("joined", "photo", "taps", "answer", "expired")  # on both streams


class Driver:
    """Plays both phones of many sessions against one server."""

    def __init__(
        self,
        base_url: str,
        photos: tuple[bytes, bytes],
        scenes: list[Scene],
        speed: float,
        seed: int,
    ) -> None:
        self.base_url = base_url
        self.photos = photos
        self.scenes = scenes
        self.speed = speed
        self.seed = seed
        self.rec = Recorder()
        # Never used (plain HTTP on loopback), but httpx builds one per client unless given
        # one: loading the CA bundle costs 35 ms per client.
        self.tls = ssl.create_default_context()

    def phone(self, role: str) -> Phone:
        """A new phone, with its own client, recording into this driver's recorder."""
        return Phone(self.rec, http_client(self.base_url, self.tls), role)

    async def pause(self, rng: np.random.Generator, step: str) -> None:
        """A person doing ``step`` (one of PAUSES)."""
        await asyncio.sleep(rng.uniform(*PAUSES[step]) / self.speed)

    async def create(self) -> tuple[Phone, str] | None:
        """The seeker's phone with a new session, and the join code; None if refused."""
        seeker = self.phone("starter")
        created = await seeker.call(CREATE, "POST", "/api/sessions", expect=201)
        if created is None:
            await seeker.close()
            return None
        body = created.json()
        seeker.enter(body["session_id"], body["token"])
        return seeker, str(body["join_code"])

    async def join(self, code: str) -> Phone | None:
        """The buddy's phone, joined with ``code``; None if refused."""
        buddy = self.phone("joiner")
        joined = await buddy.call(JOIN, "POST", "/api/sessions/join", json={"code": code})
        if joined is None:
            await buddy.close()
            return None
        body = joined.json()
        buddy.enter(body["session_id"], body["token"])
        return buddy

    async def pair(self, rng: np.random.Generator | None = None) -> tuple[Phone, Phone] | None:
        """The seeker creates a session and listens; the buddy joins with the code (after
        a person's pause, given ``rng``) and listens. None if any of it failed."""
        created = await self.create()
        if created is None:
            return None
        seeker, code = created
        seeker.listen()
        seeker.refetch()  # the phone shows the state (the QR code) at once
        if rng is not None:
            await self.pause(rng, "join")
        buddy = await self.join(code)
        if buddy is None:
            await seeker.discard()
            await seeker.close()
            return None
        buddy.listen()
        buddy.refetch()
        return seeker, buddy

    async def session(self, number: tuple[int, int]) -> bool:
        """One whole session; True when everything in it went as a phone expects."""
        rng = np.random.default_rng([self.seed, *number])
        taps = session_taps(self.scenes[int(rng.integers(len(self.scenes)))], rng)
        started = time.monotonic()
        self.rec.sessions_started += 1
        paired = await self.pair(rng)
        if paired is None:
            return False
        seeker, buddy = paired
        deleted = complete = False
        try:
            sides = await asyncio.gather(
                self.seeker_side(seeker, taps, rng), self.buddy_side(buddy, taps, rng)
            )
            if not all(sides):
                return False
            answer = [await phone.wait_for(has_answer, "the answer") for phone in paired]
            await self.pause(rng, "read")  # they read the answer, wave, find each other
            deleted = await self.delete(seeker, buddy)
            if not deleted:
                return False
            ended = [await phone.wait_event(phone.expired, "'expired'") for phone in paired]
            complete = all(answer) and all(ended)
            for phone in paired:
                missing = [kind for kind in EXPECTED_EVENTS if not phone.events[kind]]
                for kind in missing:
                    self.rec.flow(f"the {phone.role}'s stream never saw '{kind}'")
                complete = complete and not missing
                self.rec.state_fetches_per_phone.append(phone.fetches)
        finally:
            if not deleted:  # a failed or cut-off session: gone from the server all the same
                await seeker.discard()
            for phone in paired:
                await phone.close()
        if complete:
            self.rec.sessions_completed += 1
            self.rec.session_seconds.append(time.monotonic() - started)
            self.rec.finished_at.append(time.monotonic())
        return complete

    async def delete(self, seeker: Phone, *others: Phone) -> bool:
        for phone in (seeker, *others):
            await phone.settled()
        return await seeker.call(DELETE, "DELETE", seeker.url(), expect=204) is not None

    async def photo_taken(self, phone: Phone, photo: bytes, rng: np.random.Generator) -> bool:
        """Once its stream has announced it (own 'joined'): a person's pause for the photo,
        then its upload and the stored one loaded back."""
        if not await phone.wait_event(phone.live, "own 'joined'"):
            return False
        await self.pause(rng, "photo")
        return await self.upload(phone, photo)

    async def seeker_side(self, phone: Phone, taps: SessionTaps, rng: np.random.Generator) -> bool:
        """Its photo, then the buddy mark and one more landmark per PUT."""
        if not await self.photo_taken(phone, self.photos[0], rng):
            return False
        for n in range(1, LANDMARKS + 1):
            await self.pause(rng, "tap")
            body = {"landmarks": taps.seeker[:n], "friend": taps.buddy_mark}
            if not await phone.put_taps(body):
                return False
        return True

    async def buddy_side(self, phone: Phone, taps: SessionTaps, rng: np.random.Generator) -> bool:
        """Its photo; then, for each landmark the seeker taps, "find #n" (its crop) and the
        tap. (Each phone loads its overlay whenever its state shows a new answer.)"""
        if not await self.photo_taken(phone, self.photos[1], rng):
            return False
        for n in range(1, LANDMARKS + 1):
            if not await self.find_and_tap(phone, n, taps.buddy[:n], rng):
                return False
        return True

    async def find_and_tap(
        self, phone: Phone, n: int, landmarks: list[dict[str, float]], rng: np.random.Generator
    ) -> bool:
        """The buddy's landmark #n: once the seeker's #n shows, its crop, then the tap."""
        if not await phone.wait_for(seeker_tapped(n), f"the seeker's landmark #{n}"):
            return False
        if await self.crop(phone, n) is None:
            return False
        await self.pause(rng, "find")
        return await phone.put_taps({"landmarks": landmarks})

    async def crop(self, phone: Phone, n: int) -> httpx2.Response | None:
        """The seeker's landmark #n as the buddy's <img> gets it (``?token=``, a cache key)."""
        assert phone.state is not None
        seen = next(t for t in phone.state["taps"]["starter"]["landmarks"] if t["id"] == n)
        params = {"token": phone.token, "v": f"{seen['x']},{seen['y']}"}
        return await phone.call(
            CROP, "GET", phone.url(f"/landmarks/starter/{n}/crop"), params=params
        )

    async def overlay(self, phone: Phone) -> httpx2.Response | None:
        assert phone.state is not None
        params = {"token": phone.token, "v": str(phone.state["answer_version"])}
        return await phone.call(OVERLAY, "GET", phone.url(f"/overlay/{phone.role}"), params=params)

    async def upload(self, phone: Phone, photo: bytes) -> bool:
        """The photo, then the stored one as the app loads it to tap on."""
        return await self.put_photo(phone, photo) and await self.stored(phone)

    async def put_photo(self, phone: Phone, photo: bytes) -> bool:
        files = {"photo": ("photo.jpg", photo, "image/jpeg")}
        return await phone.call(PHOTO, "PUT", phone.url("/photo"), files=files) is not None

    async def stored(self, phone: Phone) -> bool:
        """Its stored photo, as the app's <img> loads it (``?token=``, a cache key)."""
        params = {"token": phone.token, "v": "1"}
        stored = await phone.call(STORED, "GET", phone.url(f"/photo/{phone.role}"), params=params)
        return stored is not None


def has_answer(state: dict[str, Any]) -> bool:
    return state.get("answer") is not None


def seeker_tapped(n: int) -> Callable[[dict[str, Any]], bool]:
    def tapped(state: dict[str, Any]) -> bool:
        seeker = state["taps"].get("starter")
        return seeker is not None and any(t["id"] == n for t in seeker["landmarks"])

    return tapped
