"""A self-signed certificate for a room server on a LAN (``room --tls-self-signed``).

A phone's browser lets a page use its camera only in a secure context: ``https://`` (or
localhost). On a LAN there is no name a public authority would certify, so the server makes its
own certificate for the addresses the phone reaches it at, keeps it beside the tokens file (the
phone's "accept" then holds across restarts), and prints its SHA-256 fingerprint: the browser
warns once, and the user compares the fingerprint its certificate viewer shows with the one the
server printed before accepting. The certificate is made anew when it lacks an address the
server is now reached at, or has expired.
"""

from __future__ import annotations

import datetime
import ipaddress
from dataclasses import dataclass
from pathlib import Path

from common import InputError, atomic_path

#: How long a certificate made here is valid.
VALID_DAYS = 825


@dataclass(frozen=True)
class Certificate:
    """A certificate's files, the addresses it names and its SHA-256 fingerprint (``AB:CD:...``)."""

    cert: Path
    key: Path
    addresses: tuple[str, ...]
    fingerprint: str
    made: bool


def paths_beside(tokens: Path) -> tuple[Path, Path]:
    """The certificate and key files kept beside a tokens file (``rooms.toml``: ``rooms-cert.pem``
    and ``rooms-key.pem``)."""
    return tokens.with_name(f"{tokens.stem}-cert.pem"), tokens.with_name(f"{tokens.stem}-key.pem")


def self_signed(cert: Path, key: Path, addresses: list[str]) -> Certificate:
    """The certificate at ``cert`` (its key at ``key``) if it names every one of ``addresses``
    (IP addresses or host names) and ``localhost`` and is valid; else one made for them, written atomically (the
    key readable by its owner only)."""
    from cryptography import x509
    from cryptography.hazmat.primitives import hashes, serialization
    from cryptography.hazmat.primitives.asymmetric import ec
    from cryptography.x509.oid import NameOID

    wanted = tuple(dict.fromkeys(["localhost", "127.0.0.1", *addresses]))
    now = datetime.datetime.now(datetime.UTC)
    if cert.is_file() and key.is_file():
        try:
            found = x509.load_pem_x509_certificate(cert.read_bytes())
            names = found.extensions.get_extension_for_class(x509.SubjectAlternativeName).value
            named = {str(n) for n in names.get_values_for_type(x509.IPAddress)} | set(
                names.get_values_for_type(x509.DNSName))
            if set(wanted) <= named and found.not_valid_after_utc > now + datetime.timedelta(days=1):
                return Certificate(cert, key, tuple(sorted(named)), _fingerprint(found), False)
        except (ValueError, x509.ExtensionNotFound) as exc:
            raise InputError(f"not a certificate toonface can read ({exc}): move it away to make a new one",
                             cert) from None
    private = ec.generate_private_key(ec.SECP256R1())
    subject = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, "toonface room server (self-signed)")])
    alternatives = [x509.IPAddress(ipaddress.ip_address(a)) if _is_ip(a) else x509.DNSName(a) for a in wanted]
    made = (x509.CertificateBuilder().subject_name(subject).issuer_name(subject).public_key(private.public_key())
            .serial_number(x509.random_serial_number()).not_valid_before(now - datetime.timedelta(minutes=5))
            .not_valid_after(now + datetime.timedelta(days=VALID_DAYS))
            .add_extension(x509.SubjectAlternativeName(alternatives), critical=False)
            .add_extension(x509.BasicConstraints(ca=False, path_length=None), critical=True)
            .add_extension(x509.ExtendedKeyUsage([x509.oid.ExtendedKeyUsageOID.SERVER_AUTH]), critical=False)
            .sign(private, hashes.SHA256()))
    with atomic_path(key, mode=0o600) as temporary:
        temporary.write_bytes(private.private_bytes(serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8,
                                                    serialization.NoEncryption()))
    with atomic_path(cert) as temporary:
        temporary.write_bytes(made.public_bytes(serialization.Encoding.PEM))
    return Certificate(cert, key, wanted, _fingerprint(made), True)


def _is_ip(address: str) -> bool:
    try:
        ipaddress.ip_address(address)
    except ValueError:
        return False
    return True


def _fingerprint(certificate) -> str:
    from cryptography.hazmat.primitives import hashes

    return ":".join(f"{b:02X}" for b in certificate.fingerprint(hashes.SHA256()))
