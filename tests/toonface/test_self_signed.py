"""The room's own certificate (``room --tls-self-signed``, issue 70 item 5): made for the addresses
asked, kept while it names them, made anew when one is new, its key the owner's alone."""

import ssl

import pytest

from common import InputError
from toonface.self_signed import paths_beside, self_signed


def test_a_certificate_is_kept_while_it_names_the_addresses_and_made_anew_for_a_new_one(tmp_path):
    cert, key = paths_beside(tmp_path / "rooms.toml")
    assert (cert.name, key.name) == ("rooms-cert.pem", "rooms-key.pem")
    first = self_signed(cert, key, ["192.168.1.20"])
    assert first.made and set(first.addresses) == {"localhost", "127.0.0.1", "192.168.1.20"}
    assert key.stat().st_mode & 0o077 == 0 and len(first.fingerprint.split(":")) == 32
    again = self_signed(cert, key, ["192.168.1.20"])
    assert not again.made and again.fingerprint == first.fingerprint  # a phone's acceptance holds
    moved = self_signed(cert, key, ["10.0.0.7"])
    assert moved.made and moved.fingerprint != first.fingerprint and "10.0.0.7" in moved.addresses
    context = ssl.create_default_context(ssl.Purpose.CLIENT_AUTH)
    context.load_cert_chain(cert, key)  # a server can serve it


def test_a_file_that_is_no_certificate_is_named_not_overwritten(tmp_path):
    cert, key = paths_beside(tmp_path / "rooms.toml")
    cert.write_text("not a certificate")
    key.write_text("nor a key")
    with pytest.raises(InputError, match="rooms-cert.pem"):
        self_signed(cert, key, ["192.168.1.20"])
    assert cert.read_text() == "not a certificate"
