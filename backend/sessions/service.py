"""The two-phone flow: pairing, photos, taps, the answer, overlays, events, expiry.

Routes stay thin and call this. Methods are synchronous (database and CPU work) and run in
a worker thread, except :meth:`SessionService.events`, the async event stream.
"""

from __future__ import annotations

import time
from collections import Counter
from collections.abc import AsyncIterator, Awaitable, Callable
from contextlib import suppress
from dataclasses import replace
from datetime import timedelta
from typing import Any, Literal, TypeVar

import anyio

from backend.clock import Clock, aware, utc_now
from backend.errors import ApiError
from backend.events import PING, RETRY, Notifier, frame
from backend.photos import crop_around, decode_photo, encode_image, store_photo
from backend.settings import Settings
from backend.storage.database import DatabaseUnavailableError
from backend.storage.repository import Event, Participant, Snapshot, Store
from shared_solver import SolveResult, draw_overlay

from . import answer as answers
from . import guessing
from .schemas import (
    CreatedSession,
    Joined,
    ParticipantState,
    PhotoStored,
    Role,
    SessionState,
    Taps,
)
from .tokens import new_join_code, new_session_id, new_token, token_hash

ImageFormat = Literal["png", "jpeg"]
MEDIA_TYPES: dict[ImageFormat, str] = {"png": "image/png", "jpeg": "image/jpeg"}
_CODE_ATTEMPTS = 20
T = TypeVar("T")


class SessionService:
    def __init__(
        self, store: Store, settings: Settings, notifier: Notifier, clock: Clock = utc_now
    ) -> None:
        self.store = store
        self.settings = settings
        self.notifier = notifier
        self.clock = clock
        # The phones whose event streams this process holds (a phone may hold two for a
        # moment, reconnecting): kept online by :meth:`keep_online`, one write for all.
        self._listening: Counter[Participant] = Counter()

    # --- pairing -------------------------------------------------------------------------

    def create(self, base_url: str) -> CreatedSession:
        """A new session for the seeker, with a join code for the buddy."""
        now = self.clock()
        token = new_token()
        expires_at = now + timedelta(seconds=self.settings.session_ttl_seconds)
        code_expires_at = min(
            now + timedelta(seconds=self.settings.join_code_ttl_seconds), expires_at
        )
        for _ in range(_CODE_ATTEMPTS):
            session_id, code = new_session_id(), new_join_code()
            if self.store.create(
                session_id,
                seeker_token_hash=token_hash(token),
                join_code=code,
                now=now,
                expires_at=expires_at,
                join_code_expires_at=code_expires_at,
            ):
                return CreatedSession(
                    session_id=session_id,
                    join_code=code,
                    join_code_expires_at=aware(code_expires_at),
                    join_url=self._join_url(base_url, code),
                    token=token,
                    expires_at=aware(expires_at),
                )
        raise ApiError(503, "busy", "Too many searches are starting at once; try again.")

    def join(self, code: str, client: str = "") -> Joined:
        """The buddy joins with the seeker's code (once, while it is valid). ``client``:
        the caller's address, whose failures are limited (:mod:`.guessing`)."""
        now = self.clock()
        guessing.refuse_guessing(self.store, client, now, self.settings)
        token = new_token()
        session_id = self.store.join(code, buddy_token_hash=token_hash(token), now=now)
        if session_id is None:
            for renewed in guessing.record_failure(self.store, client, code, now, self.settings):
                self.notifier.notify(renewed)
            raise ApiError(
                404,
                "invalid_join_code",
                "This code is unknown, already used or expired; ask your friend for a new one.",
            )
        self.notifier.notify(session_id)
        snapshot = self._snapshot(session_id)
        return Joined(session_id=session_id, token=token, expires_at=aware(snapshot.expires_at))

    def authenticate(self, token: str | None, session_id: str) -> Participant:
        """The participant a bearer token belongs to, if it opens this session."""
        if not token:
            raise ApiError(
                401, "unauthorized", "Send your session token: 'Authorization: Bearer <token>'."
            )
        participant = self.store.participant(token_hash(token), self.clock())
        if participant is None:
            raise ApiError(
                401, "unauthorized", "This token opens no session (it ended or never existed)."
            )
        if participant.session_id != session_id:
            raise ApiError(403, "forbidden", "This token opens another session.")
        return participant

    # --- what the phones see -------------------------------------------------------------

    def state(
        self, participant: Participant, base_url: str, snapshot: Snapshot | None = None
    ) -> SessionState:
        """What ``participant``'s phone shows, from ``snapshot`` if it was just read."""
        snapshot = snapshot or self._snapshot(participant.session_id)
        now = self.clock()
        online_after = now - timedelta(seconds=self.settings.online_seconds)
        taps = {
            role: None if member.taps is None else Taps.model_validate(member.taps)
            for role, member in snapshot.members.items()
        }
        task = answers.problem(taps.get("seeker"), taps.get("buddy"))
        stored = snapshot.result or {}
        code_valid = (
            snapshot.join_code is not None
            and snapshot.join_code_expires_at is not None
            and snapshot.join_code_expires_at > now
            and participant.role == "seeker"
        )
        return SessionState(
            session_id=snapshot.id,
            you=participant.role,
            version=snapshot.version,
            expires_at=aware(snapshot.expires_at),
            join_code=snapshot.join_code if code_valid else None,
            join_code_expires_at=(
                aware(snapshot.join_code_expires_at)
                if code_valid and snapshot.join_code_expires_at
                else None
            ),
            join_url=(
                self._join_url(base_url, snapshot.join_code)
                if code_valid and snapshot.join_code
                else None
            ),
            join_code_renewals=snapshot.join_code_renewals if participant.role == "seeker" else 0,
            participants={
                role: ParticipantState(
                    joined=role in snapshot.members,
                    online=role in snapshot.members
                    and (seen := snapshot.members[role].last_seen_at) is not None
                    and seen > online_after,
                )
                for role in ("seeker", "buddy")
            },
            photos={
                role: (
                    PhotoStored(width=info.width, height=info.height, scale=info.scale)
                    if (info := snapshot.photos.get(role)) is not None
                    else None
                )
                for role in ("seeker", "buddy")
            },
            taps={role: taps.get(role) for role in ("seeker", "buddy")},
            landmarks_needed=task.landmarks_needed(stored.get("result")),
            result=stored.get("result"),
            result_version=snapshot.result_version if "result" in stored else None,
            result_landmark_ids=stored.get("landmark_ids"),
            result_error=stored.get("error"),
        )

    # --- photos and taps -----------------------------------------------------------------

    def put_photo(self, participant: Participant, data: bytes) -> PhotoStored:
        """Store the caller's photo (replacing any earlier one, whose taps go with it)."""
        photo = store_photo(
            data,
            max_pixels=self.settings.max_photo_pixels,
            max_side=self.settings.stored_photo_side,
        )
        self.store.put_photo(participant, photo, self.clock())
        self.notifier.notify(participant.session_id)
        return PhotoStored(width=photo.width, height=photo.height, scale=photo.scale)

    def put_taps(self, participant: Participant, taps: Taps, base_url: str) -> SessionState:
        """Replace the caller's taps, then answer again when both photos allow it."""
        snapshot = self._snapshot(participant.session_id)
        photo = snapshot.photos.get(participant.role)
        if photo is None:
            raise ApiError(409, "photo_missing", "Upload your photo before tapping on it.")
        self._check_taps(participant.role, taps, (photo.width, photo.height))
        # Answered before writing, so that the taps and their answer are one write; unless
        # another change comes in between, which makes that answer stale.
        tapped = taps.model_dump(mode="json")
        member = snapshot.members[participant.role]
        after = replace(
            snapshot, members=snapshot.members | {member.role: replace(member, taps=tapped)}
        )
        found = self._solve(after)
        answer = None if found is None else (snapshot.version, found)
        version, answered = self.store.put_taps(participant, tapped, self.clock(), answer)
        self.notifier.notify(participant.session_id)
        if version != snapshot.version + 1:  # overtaken: answer the session as it now is
            return self.state(participant, base_url, self._answer(participant.session_id, version))
        shown = replace(
            after,
            version=version,
            result=found if answered else None,
            result_version=version if answered else None,
        )
        return self.state(participant, base_url, shown)

    def _check_taps(self, role: str, taps: Taps, size: tuple[int, int]) -> None:
        if len(taps.landmarks) > self.settings.max_landmarks:
            raise ApiError(
                422,
                "too_many_landmarks",
                f"{len(taps.landmarks)} landmarks; at most {self.settings.max_landmarks}.",
            )
        ids = [tap.id for tap in taps.landmarks]
        if len(set(ids)) != len(ids):
            repeated = sorted({i for i in ids if ids.count(i) > 1})
            raise ApiError(
                422, "duplicate_landmark", f"Landmark #{repeated[0]} is tapped twice; keep one."
            )
        if role == "seeker" and taps.epipole2 is not None:
            raise ApiError(
                422, "not_your_mark", "Only the buddy marks the seeker (epipole2) in their photo."
            )
        if role == "buddy" and (taps.epipole1 is not None or taps.epipolar_line1 is not None):
            raise ApiError(
                422,
                "not_your_mark",
                "Only the seeker marks the buddy (epipole1 or epipolar_line1) in their photo.",
            )
        if taps.epipole1 is not None and taps.epipolar_line1 is not None:
            raise ApiError(
                422,
                "conflicting_inputs",
                "Mark the buddy either as a point or as a line, not both.",
            )
        if taps.epipolar_line1 is not None and taps.epipolar_line1[:2] == (0.0, 0.0):
            raise ApiError(
                422, "invalid_line", "epipolar_line1 must be [a, b, c] with a or b nonzero."
            )
        width, height = size
        marks = [(f"landmark #{t.id}", t.x, t.y) for t in taps.landmarks]
        for name, point in (("the buddy mark", taps.epipole1), ("the seeker mark", taps.epipole2)):
            if point is not None:
                marks.append((name, *point))
        for name, x, y in marks:
            if not (0 <= x <= width and 0 <= y <= height):
                raise ApiError(
                    422,
                    "outside_photo",
                    # :g, not :.0f: 1e308 is shown as such, not as 309 digits.
                    f"{name.capitalize()} at ({x:g}, {y:g}) is outside the photo "
                    f"({width} x {height} px).",
                )

    def _answer(self, session_id: str, version: int) -> Snapshot | None:
        """Solve for this version if there is enough; record it unless overtaken. The
        session as it then is (None: overtaken by a newer change)."""
        snapshot = self._snapshot(session_id)
        if snapshot.version != version:
            return None  # a newer change is being answered
        found = self._solve(snapshot)
        if found is None:
            return snapshot
        if not self.store.put_result(session_id, version, found, self.clock()):
            return None
        self.notifier.notify(session_id)
        return replace(snapshot, result=found, result_version=version)

    def _solve(self, snapshot: Snapshot) -> dict[str, Any] | None:
        """The answer for the session as ``snapshot`` has it; None when there is not enough
        to answer (a photo missing, too few taps)."""
        seeker, buddy = (snapshot.members.get(role) for role in ("seeker", "buddy"))
        photo1, photo2 = snapshot.photos.get("seeker"), snapshot.photos.get("buddy")
        if seeker is None or buddy is None or photo1 is None or photo2 is None:
            return None
        task = answers.problem(
            None if seeker.taps is None else Taps.model_validate(seeker.taps),
            None if buddy.taps is None else Taps.model_validate(buddy.taps),
        )
        if not task.solvable:
            return None
        return answers.answer(
            task,
            tap_sigma=self.settings.tap_sigma,
            image_size1=(photo1.width, photo1.height),
            image_size2=(photo2.width, photo2.height),
        )

    # --- pictures ------------------------------------------------------------------------

    def overlay(self, participant: Participant, role: Role, fmt: ImageFormat) -> bytes:
        """``role``'s photo with the answer drawn for that phone, drawn for each request and
        never kept (a phone loads each answer's overlay once; its own cache keeps it)."""
        snapshot = self._snapshot(participant.session_id)
        if snapshot.result is None:
            # An answer may be due but not yet recorded: a change overtook the write that
            # carried it, and its writer is answering again. Answer here rather than send
            # a phone that just read "answered" away empty.
            snapshot = self._answer(snapshot.id, snapshot.version) or snapshot
        stored = snapshot.result or {}
        if "result" not in stored or snapshot.result_version is None:
            raise ApiError(
                409, "no_result", "There is no answer yet; tap more landmarks in both photos."
            )
        photo = self.store.photo(snapshot.id, role)
        member = snapshot.members.get(role)
        if photo is None or member is None or member.taps is None:
            raise ApiError(409, "no_result", "That photo changed; the answer is being renewed.")
        taps = {tap.id: (tap.x, tap.y) for tap in Taps.model_validate(member.taps).landmarks}
        ids: list[int] = stored["landmark_ids"]
        drawn = draw_overlay(
            decode_photo(photo.data),
            SolveResult.model_validate(stored["result"]),
            view="buddy" if role == "buddy" else "seeker",
            points=[taps[i] for i in ids],
            labels=ids,
        )
        return encode_image(drawn, format=fmt)

    def photo(self, participant: Participant, role: Role) -> bytes:
        """``role``'s photo as stored (upright JPEG): what that phone taps on."""
        photo = self.store.photo(participant.session_id, role)
        if photo is None:
            raise ApiError(404, "photo_missing", f"The {role} has not uploaded a photo yet.")
        return photo.data

    def crop(self, participant: Participant, role: Role, landmark_id: int) -> bytes:
        """A small picture around one landmark of ``role``'s photo: "find this"."""
        snapshot = self._snapshot(participant.session_id)
        member = snapshot.members.get(role)
        taps = None if member is None or member.taps is None else Taps.model_validate(member.taps)
        tap = next((t for t in taps.landmarks if t.id == landmark_id), None) if taps else None
        photo = self.store.photo(snapshot.id, role) if tap is not None else None
        if tap is None or photo is None:
            raise ApiError(404, "landmark_not_found", f"The {role} has no landmark #{landmark_id}.")
        return crop_around(photo.data, tap.x, tap.y)

    # --- ending --------------------------------------------------------------------------

    def delete(self, participant: Participant) -> None:
        """Delete now: the session and everything of it, for both phones."""
        self.store.delete(participant.session_id)
        self.notifier.notify(participant.session_id)

    def sweep(self) -> list[str]:
        """Delete the sessions whose time is up (their streams say 'expired') and failed
        joins out of every window; erase what deletions left in the database's files."""
        now = self.clock()
        gone = self.store.delete_expired(now)
        for session_id in gone:
            self.notifier.notify(session_id)
        window = timedelta(seconds=self.settings.join_attempt_window_seconds)
        self.store.forget_join_failures(now - window)
        self.store.erase_deleted()  # deleted bytes out of the database's files
        return gone

    def erase_deleted(self) -> None:
        """Erase what deletions left in the database's files (see the store)."""
        self.store.erase_deleted()

    def keep_online(self) -> None:
        """Mark every phone listening here as seen now (every ``online_seconds / 3``: a
        listening phone stays online; one that stops being heard goes offline)."""
        if listening := list(self._listening):
            self.store.seen_all(listening, self.clock())

    def watch(self, after: int | None) -> int:
        """Wake the streams of sessions that another process changed or deleted since event
        ``after`` (None: start watching now); the newest event id. For several worker
        processes on one SQLite file, which have no LISTEN/NOTIFY; a change made here wakes
        its streams once more, which then find nothing new."""
        newest, changed = self.store.changes_since(after, self.notifier.watched())
        for session_id in changed:
            self.notifier.notify(session_id)
        return newest

    def healthy(self) -> bool:
        return self.store.healthy()

    # --- the event stream ----------------------------------------------------------------

    async def events(
        self,
        participant: Participant,
        last_event_id: int | None,
        disconnected: Callable[[], Awaitable[bool]],
    ) -> AsyncIterator[str]:
        """Server-sent events for one phone: 'this changed', pings, and presence.

        Replays what came after ``last_event_id`` (a reconnecting phone). Marks the phone
        online while connected, offline (and tells the other phone) when it goes. Reads the
        events when woken by a change (here or, on PostgreSQL, on any replica) and every
        ``event_poll_seconds`` in case a wake-up was lost; pings in between. Outlives an outage of
        the database: it keeps pinging and reads again when woken after it.
        """
        session_id, role = participant.session_id, participant.role
        keepalive, poll = self.settings.keepalive_seconds, self.settings.event_poll_seconds
        # Subscribed before reading anything: a change committed after that read wakes it.
        # The first bytes (the headers: EventSource's "open", when the phone fetches the
        # state) go out after it, so every change the phone's fetch may miss is streamed.
        with self.notifier.subscribe(session_id) as changed:
            try:
                await self._in_thread(self.store.seen, participant, self.clock())
                if last_event_id is None:
                    last_event_id = await self._in_thread(self.store.last_event_id, session_id)
                snapshot = await self._in_thread(self.store.snapshot, session_id)
            except DatabaseUnavailableError:
                return  # gone since this request was authenticated: the phone retries
            yield RETRY
            if snapshot is None:
                yield frame(None, "expired", {"reason": "The session ended."})
                return
            after = last_event_id
            await self._presence(session_id, "joined", {"role": role, "online": True})
            self._listening[participant] += 1
            try:
                pinged = time.monotonic()
                while True:
                    changed.clear()  # a change from now on wakes the wait below
                    events = await self._events_after(session_id, after)
                    polled = time.monotonic()
                    # Gone (deleted, swept), or past its time and about to be swept: it ended.
                    if events is None or self.clock() >= snapshot.expires_at:
                        yield frame(None, "expired", {"reason": "The session ended."})
                        return
                    for event in events:
                        yield frame(event.id, event.type, event.data)
                        after = event.id
                    # Until a change, the next poll or the end of the session; pinging.
                    while True:
                        if await disconnected():
                            return
                        now = time.monotonic()
                        if now - pinged >= keepalive:
                            yield PING
                            pinged = now
                        if now - polled >= poll or self.clock() >= snapshot.expires_at:
                            break
                        if await changed.wait(min(pinged + keepalive, polled + poll) - now):
                            break
            finally:
                # Shielded: the client is gone and the stream is being cancelled.
                with anyio.CancelScope(shield=True):
                    await self._hang_up(participant)

    async def _hang_up(self, participant: Participant) -> None:
        """A stream of ``participant`` ended: offline, and the other phone told, unless
        another stream of it is still open here (a phone that reconnected)."""
        self._listening[participant] -= 1
        if self._listening[participant] > 0:
            return
        del self._listening[participant]
        with suppress(DatabaseUnavailableError):
            await self._in_thread(self.store.seen, participant, None)
            await self._presence(
                participant.session_id, "left", {"role": participant.role, "online": False}
            )

    async def _events_after(self, session_id: str, after: int) -> list[Event] | None:
        """The session's events after ``after`` (None: it is gone); none while the database
        is unavailable (when it is back, every stream is woken to read again)."""
        try:
            return await self._in_thread(self.store.events_after, session_id, after)
        except DatabaseUnavailableError:
            return []

    async def _presence(self, session_id: str, type_: str, data: dict[str, object]) -> None:
        """Tell the other phone this one came or went (skipped while the database is away:
        presence also shows in the state, from ``seen``)."""
        with suppress(DatabaseUnavailableError):
            await self._in_thread(self.store.publish, session_id, type_, data, self.clock())
        self.notifier.notify(session_id)

    @staticmethod
    async def _in_thread(function: Callable[..., T], *args: object) -> T:
        return await anyio.to_thread.run_sync(lambda: function(*args))

    # --- helpers -------------------------------------------------------------------------

    def _snapshot(self, session_id: str) -> Snapshot:
        snapshot = self.store.snapshot(session_id)
        if snapshot is None:
            raise ApiError(404, "session_not_found", "This session has ended.")
        return snapshot

    def _join_url(self, base_url: str, code: str) -> str:
        base = (self.settings.public_url or base_url).rstrip("/")
        return f"{base}/join/{code}"
