"""The room server, a first step of issue 45: a performer and a viewer both connect out to it over
WebSocket (no port opened at either end), the stream's own packets pass through untouched, and
wrong tokens, foreign pages, oversized and flooding messages are refused and counted."""

import asyncio

import aiohttp
import numpy as np
import pytest

from stream.framing import MAX_PACKET
from stream.packets import StreamWriter
from stream.playout import Playout
from stream.receiver import StreamReceiver
from stream.websocket import LinkError, WebSocketLink
from toon import standard_neutral
from toonface.cli import main
from toonface.room.server import Rooms
from toonface.room.threaded import in_thread

TOKENS = {"demo": ("perform-secret-0123456789", "watch-secret-0123456789")}


def room_server(rooms: Rooms, ssl_context=None):
    """The room server on a free loopback port, in its own thread; its ws:// (wss://) base."""
    return in_thread(rooms, ssl_context=ssl_context)


@pytest.mark.slow  # a second and a half of send: make test runs it (make test-fast stays under a minute)
def test_a_performer_reaches_a_viewer_through_the_room_and_acknowledgements_come_back(capsys):
    rooms = Rooms(TOKENS)
    with room_server(rooms) as base:
        url = f"{base}/r/demo"
        link = WebSocketLink(url, TOKENS["demo"][1], "watch")  # a viewer behind NAT: it binds nothing, connects out
        with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral()), link=link) as receiver:
            assert receiver.sock is link
            assert main(["send", "synthetic", "--to", url, "--token", TOKENS["demo"][0], "--seconds", "1.5",
                         "--stats"]) == 0
            assert receiver.wait_for_packets(40, timeout=10)
        out = capsys.readouterr().out
    assert f"packets to {url}: payload" in out  # send's summary names the room
    stats = [line for line in out.splitlines() if line.startswith("{")][-1]
    assert '"acks": 0' not in stats  # the viewer's acknowledgements came back through the room
    assert receiver.reader.lost == 0 and rooms.rooms["demo"].forwarded >= 40
    values, state = receiver.values_at()
    assert state in ("live", "concealed", "recovering") and np.all((values >= 0) & (values <= 1))


@pytest.mark.slow  # a send that is refused, and a flood: make test runs it
def test_wrong_tokens_foreign_pages_oversized_and_flooding_messages_are_refused_and_counted(capsys):
    rooms = Rooms(TOKENS, rate_limit=50)
    with room_server(rooms) as base:
        with pytest.raises(LinkError, match="no such room, or not with that token"):
            WebSocketLink(f"{base}/r/demo", "guess", "watch")
        with pytest.raises(LinkError, match="403"):
            WebSocketLink(f"{base}/r/other", TOKENS["demo"][1], "watch")
        assert main(["send", "synthetic", "--to", f"{base}/r/demo", "--token", "wrong", "--seconds", "0.2"]) == 2
        assert "no such room, or not with that token" in capsys.readouterr().err

        async def attempts() -> tuple[int, bool]:
            async with aiohttp.ClientSession() as session:
                try:  # a page of another site opening a socket to the room
                    await session.ws_connect(f"{base}/r/demo/ws?role=watch", headers={
                        "Origin": "https://elsewhere.example", "Authorization": f"Bearer {TOKENS['demo'][1]}"})
                    foreign = 0
                except aiohttp.WSServerHandshakeError as exc:
                    foreign = exc.status
                headers = {"Authorization": f"Bearer {TOKENS['demo'][0]}"}
                async with session.ws_connect(f"{base}/r/demo/ws?role=perform", headers=headers) as ws:
                    packet = StreamWriter(60.0, stream=9, frames_per_packet=1).push(standard_neutral(), 0.0)
                    for _ in range(120):  # a flood: over 50 a second
                        await ws.send_bytes(packet)
                    await ws.send_bytes(b"\\0" * (MAX_PACKET + 10))  # too large: the server ends the socket
                    message = await ws.receive(timeout=5)
                    while message.type == aiohttp.WSMsgType.TEXT:  # the server's ask of the performer's clock
                        message = await ws.receive(timeout=5)
                    closed = message.type in (aiohttp.WSMsgType.CLOSE, aiohttp.WSMsgType.CLOSED)
            return foreign, closed

        foreign, closed = asyncio.run(attempts())
    assert foreign == 403 and rooms.refused["origin"] == 1 and rooms.refused["token"] >= 2
    assert rooms.refused["room"] == 1 and closed
    refused = rooms.rooms["demo"].refused
    assert refused["flood"] >= 60 and refused["size"] == 1


def test_the_room_command_makes_tokens_once_and_keeps_them(tmp_path, capsys):
    tokens = tmp_path / "rooms.toml"
    assert main(["room", "--listen", "127.0.0.1:0", "--room", "demo", "--tokens", str(tokens), "--seconds", "0.1"]) == 0
    first = capsys.readouterr().out
    assert "perform  toonface send SOURCE --to ws://127.0.0.1:" in first and "/r/demo --token" in first
    assert oct(tokens.stat().st_mode & 0o777) == "0o600"
    assert main(["room", "--listen", "127.0.0.1:0", "--tokens", str(tokens), "--seconds", "0.1"]) == 0
    again = capsys.readouterr().out
    assert [line.split("--token ")[1] for line in first.splitlines() if "--token" in line] == \
        [line.split("--token ")[1] for line in again.splitlines() if "--token" in line]  # kept across restarts
    assert main(["room", "--listen", "127.0.0.1:0", "--tokens", str(tmp_path / "none.toml")]) == 2


def self_signed(folder):
    """A certificate and key for 127.0.0.1, signed by themselves (PEM files)."""
    import datetime
    import ipaddress

    from cryptography import x509
    from cryptography.hazmat.primitives import hashes, serialization
    from cryptography.hazmat.primitives.asymmetric import ec
    from cryptography.x509.oid import NameOID

    key = ec.generate_private_key(ec.SECP256R1())
    name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, "toonface room test")])
    now = datetime.datetime.now(datetime.UTC)
    cert = (x509.CertificateBuilder().subject_name(name).issuer_name(name).public_key(key.public_key())
            .serial_number(x509.random_serial_number()).not_valid_before(now - datetime.timedelta(minutes=1))
            .not_valid_after(now + datetime.timedelta(days=1))
            .add_extension(x509.SubjectAlternativeName([x509.IPAddress(ipaddress.ip_address("127.0.0.1"))]), False)
            .add_extension(x509.BasicConstraints(ca=True, path_length=None), True)
            .sign(key, hashes.SHA256()))
    (folder / "room.pem").write_bytes(cert.public_bytes(serialization.Encoding.PEM))
    (folder / "room.key").write_bytes(key.private_bytes(serialization.Encoding.PEM,
                                                        serialization.PrivateFormat.PKCS8,
                                                        serialization.NoEncryption()))
    return folder / "room.pem", folder / "room.key"


def test_wss_with_a_self_signed_certificate_is_trusted_only_when_given(tmp_path):
    import ssl

    cert, key = self_signed(tmp_path)
    context = ssl.create_default_context(ssl.Purpose.CLIENT_AUTH)
    context.load_cert_chain(cert, key)
    with room_server(Rooms(TOKENS), context) as base:
        url = f"{base}/r/demo"
        with pytest.raises(LinkError, match="certificate"):
            WebSocketLink(url, TOKENS["demo"][1], "watch")  # not trusted by the system
        link = WebSocketLink(url, TOKENS["demo"][1], "watch", ca_file=str(cert))
        link.close()
        assert link.closed.is_set()


def test_a_room_on_every_interface_prints_links_other_machines_can_open(tmp_path, capsys, monkeypatch):
    """Issue 68: under --listen 0.0.0.0 the links said 127.0.0.1, which no other machine opens."""
    from toonface import web_hosts

    monkeypatch.setattr(web_hosts, "reachable_addresses", lambda: ["192.168.1.23", "10.0.0.7"])
    tokens = tmp_path / "rooms.toml"
    assert main(["room", "--listen", "0.0.0.0:0", "--room", "demo", "--tokens", str(tokens), "--seconds", "0.1"]) == 0
    out = capsys.readouterr().out
    assert "browser  http://192.168.1.23:" in out and "camera   http://192.168.1.23:" in out
    assert "every interface: also at 10.0.0.7, 127.0.0.1 from this machine" in out
    assert "127.0.0.1:" not in out.split("every interface")[1]  # no link names it
    monkeypatch.setattr(web_hosts, "reachable_addresses", lambda: [])
    assert main(["room", "--listen", "0.0.0.0:0", "--tokens", str(tokens), "--seconds", "0.1"]) == 0
    assert "no address other machines reach was found: 127.0.0.1 only" in capsys.readouterr().out


def test_the_machines_reachable_addresses_are_real_and_never_loopback():
    import ipaddress
    import socket

    from toonface.web_hosts import reachable_addresses

    for address in reachable_addresses():
        ip = ipaddress.ip_address(address)
        assert not ip.is_loopback and not ip.is_link_local
        with socket.socket() as probe:
            probe.bind((address, 0))  # an address of this machine: it can be bound


def test_the_counters_say_what_each_room_did_since_the_last_line():
    """Issue 68: the room server showed no counters. One line per room, what changed since the
    last line and in all, refusals by reason."""
    from toonface.room.counters import Counters

    rooms = Rooms(TOKENS)
    room = rooms.rooms["demo"]
    counters = Counters()
    room.forwarded, room.skipped = 120, 3
    room.refused["token"] += 2
    rooms.refused["room"] += 1
    assert counters.line(rooms) == ("demo: 0 performing, 0 watching, 120 packets relayed (120 in all), 3 missed by "
                                    "slow viewers (3), refused 2 (token 2); refused before a room: 1 (room 1)")
    room.forwarded += 30
    assert "30 packets relayed (150 in all), 0 missed by slow viewers (3)" in counters.line(rooms)


@pytest.mark.slow  # a server process: make test runs it
def test_room_stats_prints_a_line_every_so_often_with_a_performer_in_it(tmp_path):
    import subprocess
    import sys

    from tests.helpers.pubsub import free_port

    port = free_port()
    server = subprocess.Popen([sys.executable, "-m", "toonface", "room", "--listen", f"127.0.0.1:{port}", "--room",
                               "demo", "--tokens", str(tmp_path / "rooms.toml"), "--stats", "0.5", "--seconds", "30"],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        lines = [server.stdout.readline() for _ in range(5)]
        perform = lines[1].rsplit("--token ", 1)[1].strip()
        link = WebSocketLink(f"ws://127.0.0.1:{port}/r/demo", perform, "perform")
        from stream.sender import StreamSender

        sender = StreamSender((link.where, 0), StreamWriter(30.0, frames_per_packet=1, stream=7), link=link)
        try:
            for k in range(30):
                sender.write(k / 30, standard_neutral())
            said = ""
            while "1 performing" not in said:  # within the server's --seconds, or readline's end fails it
                said = server.stdout.readline()
                assert said, "the server ended without a counters line"
        finally:
            sender.close()
        assert said.startswith("demo: 1 performing, 0 watching, ") and "refused before a room: 0" in said
    finally:
        server.kill()
        server.wait()
        server.stdout.close()
