"""A TLS certificate made at start-up, for a cluster with no certificate of its own.

trustme makes a certificate authority for this run only and a server certificate it signs:
a phone warns about it as about any self-signed certificate, while tests and scripts can
verify the connection properly by trusting the authority's file (``authority.pem``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import trustme


@dataclass(frozen=True)
class Certificate:
    certificate: Path  # the server's certificate and its chain (PEM), for nginx
    key: Path  # its private key (PEM), readable by its owner only
    authority: Path | None  # the certificate to trust, when made here


def made_at_start_up(folder: Path, names: Sequence[str]) -> Certificate:
    """A certificate for ``names`` (IP addresses or host names), written into ``folder``."""
    authority = trustme.CA(organization_name="Buddy Search run-cluster")
    issued = authority.issue_cert(*names)
    files = Certificate(folder / "certificate.pem", folder / "key.pem", folder / "authority.pem")
    issued.cert_chain_pems[0].write_to_path(str(files.certificate))
    for extra in issued.cert_chain_pems[1:]:
        extra.write_to_path(str(files.certificate), append=True)
    files.key.touch(mode=0o600)
    issued.private_key_pem.write_to_path(str(files.key))
    authority.cert_pem.write_to_path(str(folder / "authority.pem"))
    return files
