"""Secrets of a session: ids, participants' tokens (stored only hashed) and join codes."""

from __future__ import annotations

import hashlib
import secrets


def new_session_id() -> str:
    return secrets.token_hex(16)


def new_token() -> str:
    """A bearer token: 256 random bits (twice the 128 that put guessing out of reach),
    URL-safe, 43 characters."""
    return secrets.token_urlsafe(32)


def token_hash(token: str) -> str:
    """What the database keeps: a leaked database does not open any session."""
    return hashlib.sha256(token.encode()).hexdigest()


def new_join_code() -> str:
    """Six digits, easy to read out across a venue: only 10^6 codes, so guessing them is
    limited (:mod:`.guessing`)."""
    return f"{secrets.randbelow(1_000_000):06d}"
