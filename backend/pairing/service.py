"""Starting a search, joining it, knowing who asks, and ending it (now, or when its time
is up)."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import timedelta

from backend.clock import Clock, aware
from backend.errors import ErrorCode, RefusedError
from backend.eventstream.notifier import Notifier
from backend.participants import Participant
from backend.settings import Settings
from backend.storage.database import Database
from backend.storage.snapshot import read_snapshot

from . import guessing
from .repository import Pairings
from .schemas import CreatedSession, Joined
from .tokens import new_join_code, new_session_id, new_token, token_hash

_CODE_ATTEMPTS = 20


@dataclass(kw_only=True)
class PairingService:
    database: Database
    store: Pairings
    settings: Settings
    notifier: Notifier
    clock: Clock

    def create(self, base_url: str) -> CreatedSession:
        """A new search, with a join code for the friend."""
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
                starter_token_hash=token_hash(token),
                join_code=code,
                now=now,
                expires_at=expires_at,
                join_code_expires_at=code_expires_at,
            ):
                return CreatedSession(
                    session_id=session_id,
                    join_code=code,
                    join_code_expires_at=aware(code_expires_at),
                    join_url=self.join_url(base_url, code),
                    token=token,
                    expires_at=aware(expires_at),
                )
        raise RefusedError(ErrorCode.BUSY, "Too many searches are starting at once; try again.")

    def join(self, code: str, client: str = "") -> Joined:
        """The friend joins with the starter's code (once, while it is valid). ``client``:
        the caller's address, whose failures are limited (:mod:`.guessing`)."""
        now = self.clock()
        guessing.refuse_guessing(self.store, client, now, self.settings)
        token = new_token()
        session_id = self.store.join(code, joiner_token_hash=token_hash(token), now=now)
        if session_id is None:
            for renewed in guessing.record_failure(self.store, client, code, now, self.settings):
                self.notifier.notify(renewed)
            raise RefusedError(
                ErrorCode.INVALID_JOIN_CODE,
                "This code is unknown, already used or expired; ask your friend for a new one.",
            )
        self.notifier.notify(session_id)
        snapshot = read_snapshot(self.database, session_id)
        if snapshot is None:
            raise RefusedError(ErrorCode.SESSION_NOT_FOUND, "This session has ended.")
        return Joined(session_id=session_id, token=token, expires_at=aware(snapshot.expires_at))

    def authenticate(self, token: str | None, session_id: str) -> Participant:
        """The participant a bearer token belongs to, if it opens this session."""
        if not token:
            raise RefusedError(
                ErrorCode.UNAUTHORIZED, "Send your session token: 'Authorization: Bearer <token>'."
            )
        participant = self.store.participant(token_hash(token), self.clock())
        if participant is None:
            raise RefusedError(
                ErrorCode.UNAUTHORIZED, "This token opens no session (it ended or never existed)."
            )
        if participant.session_id != session_id:
            raise RefusedError(ErrorCode.FORBIDDEN, "This token opens another session.")
        return participant

    def join_url(self, base_url: str, code: str) -> str:
        base = (self.settings.public_url or base_url).rstrip("/")
        return f"{base}/join/{code}"

    def delete(self, participant: Participant) -> None:
        """Delete now: the session and everything of it, for both phones."""
        self.store.delete(participant.session_id)
        self.notifier.notify(participant.session_id)

    def sweep(self) -> list[str]:
        """Delete the sessions whose time is up (their streams say 'expired') and failed
        joins out of every window."""
        now = self.clock()
        gone = self.store.delete_expired(now)
        for session_id in gone:
            self.notifier.notify(session_id)
        window = timedelta(seconds=self.settings.join_attempt_window_seconds)
        self.store.forget_join_failures(now - window)
        return gone
