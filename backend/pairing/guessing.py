"""Limits on guessing join codes: failed joins are counted per code, per client address
and overall.

A join code is eight digits valid 10 minutes: a search number (four digits) and a secret
(four more). Every wrong code gets the same answer, so a guesser cannot tell which numbers
are live. Counted in the database, which replicas share:

- a wrong code that names a live search's number counts against that search's code; after
  ``join_failures_per_code`` such failures the code is renewed (a new number and secret,
  shown on the starter's phone), so one code is never tried more than that many times;
- one address may fail ``join_failures_per_client`` times per window (sliding), then it
  waits until its oldest failure leaves the window;
- once everyone together has failed ``join_failures_overall`` times in the window, guessing
  from many addresses is taken to be under way: an address that has failed in the window
  waits until its failures leave it, and one that has not may still try (one guess each).

Only failures count: the thousands of phones behind one carrier address at a stadium that
type their code right are not limited at all. A refused attempt is not tried, even with a
right code (else the limit would not limit), and not recorded.
"""

from __future__ import annotations

import ipaddress
import math
from datetime import datetime, timedelta

from backend.errors import ErrorCode, RefusedError
from backend.settings import Settings

from .repository import CodeRenewal, Pairings
from .tokens import codes_of_search, new_join_code


def client_key(host: str) -> str:
    """What the limits count: an IPv4 address, or the /64 network of an IPv6 address (one
    subscriber is given a whole /64: counting single IPv6 addresses would give each one
    2^64 fresh addresses)."""
    try:
        address = ipaddress.ip_address(host)
    except ValueError:
        return host[:64] or "unknown"  # not an IP address (a test client, a Unix socket)
    if isinstance(address, ipaddress.IPv6Address):
        if address.ipv4_mapped is not None:
            return str(address.ipv4_mapped)
        return str(ipaddress.IPv6Network((address, 64), strict=False))
    return str(address)


def refuse_guessing(store: Pairings, client: str, now: datetime, settings: Settings) -> None:
    """Refuse with ``too_many_attempts`` (and the seconds to wait) if ``client`` may not try a
    join code now."""
    window = timedelta(seconds=settings.join_attempt_window_seconds)
    failures = store.join_failures(client_key(client), now - window)
    if failures.client >= settings.join_failures_per_client and failures.client_oldest:
        until, why = failures.client_oldest + window, "Too many wrong codes from your network"
    elif failures.overall >= settings.join_failures_overall and failures.client_newest:
        until, why = failures.client_newest + window, "Many wrong codes are being tried just now"
    else:
        return
    seconds = max(1, math.ceil((until - now).total_seconds()))
    minutes = max(1, round(seconds / 60))
    raise RefusedError(
        ErrorCode.TOO_MANY_ATTEMPTS,
        f"{why}; try again in {minutes} minute{'s' if minutes > 1 else ''}.",
        retry_after=seconds,
    )


def record_failure(
    store: Pairings, client: str, code: str, now: datetime, settings: Settings
) -> list[str]:
    """Count a failed join with ``code``, against ``client`` and against the live code of
    the search it names; returns the sessions whose code this renewed."""
    renewal = CodeRenewal(
        after_failures=settings.join_failures_per_code,
        new_code=new_join_code,
        valid_for=timedelta(seconds=settings.join_code_ttl_seconds),
    )
    return store.record_join_failure(client_key(client), codes_of_search(code), now, renewal)
