"""Secrets of a session: ids, participants' tokens (stored only hashed) and join codes."""

from __future__ import annotations

import hashlib
import secrets

from backend.limits import JOIN_CODE_LENGTH


def new_session_id() -> str:
    return secrets.token_hex(16)


def new_token() -> str:
    """A bearer token: 256 random bits (twice the 128 that put guessing out of reach),
    URL-safe, 43 characters."""
    return secrets.token_urlsafe(32)


def token_hash(token: str) -> str:
    """What the database keeps: a leaked database does not open any session."""
    return hashlib.sha256(token.encode()).hexdigest()


# A join code is a search number and a secret, four digits each: "4829 1375". A wrong code
# still names a search (by its number), so failures can be counted against that search's
# code, and a code is renewed after a few (:mod:`.guessing`).
CODE_DIGITS = JOIN_CODE_LENGTH
NUMBER_DIGITS = CODE_DIGITS // 2
SECRET_DIGITS = CODE_DIGITS - NUMBER_DIGITS


def new_join_code() -> str:
    """Eight random digits, easy to read out across a venue: 10^8 codes, of which a
    guesser cannot tell the live ones (every wrong code gets the same answer)."""
    return f"{secrets.randbelow(10**CODE_DIGITS):0{CODE_DIGITS}d}"


def codes_of_search(code: str) -> tuple[str, str]:
    """The first and the last code with ``code``'s search number (its first four digits)."""
    number = code[:NUMBER_DIGITS]
    return number + "0" * SECRET_DIGITS, number + "9" * SECRET_DIGITS
