"""Rooms shared by several room server processes through NATS (issue 45): a viewer on one server
sees a performer on another, its acknowledgements find the performer, and a viewer whose server
stops reconnects to another on the same address within two seconds."""

import asyncio
import json
import socket
import threading
import time

import numpy as np
import pytest
from pubsub import NATS_TOKEN, free_port, nats_server

from stream.packets import StreamWriter
from stream.playout import Playout
from stream.receiver import StreamReceiver
from stream.sender import StreamSender
from stream.websocket import WebSocketLink
from toon import standard_neutral
from toonface.room.pubsub import shown
from toonface.room.server import Rooms
from toonface.room.threaded import in_thread

TOKENS = {"demo": ("perform-secret-0123456789", "watch-secret-0123456789")}


def _performer(base: str) -> StreamSender:
    link = WebSocketLink(f"{base}/r/demo", TOKENS["demo"][0], "perform")
    return StreamSender((link.where, 0), StreamWriter(30.0, frames_per_packet=1, stream=0x51), link=link)


@pytest.mark.slow  # over a second: make test runs it, test-fast does not
def test_a_viewer_on_one_server_sees_a_performer_on_another_and_answers_it():
    with nats_server() as url:
        one, two = Rooms(TOKENS, pubsub=url), Rooms(TOKENS, pubsub=url)
        with in_thread(one) as first, in_thread(two) as second:
            link = WebSocketLink(f"{second}/r/demo", TOKENS["demo"][1], "watch")
            with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral()), link=link) as receiver:
                sender = _performer(first)
                try:
                    for k in range(60):  # two seconds of frames, sent at once
                        sender.write(k / 30, standard_neutral())
                    assert receiver.wait_for_packets(60, timeout=10)
                    deadline = time.monotonic() + 10
                    while sender.acks == 0 and time.monotonic() < deadline:  # the viewer's answer, back through NATS
                        sender.write(2.0, standard_neutral())
                        receiver.wait_for_packets(10_000, timeout=0.1)
                finally:
                    sender.close()
    assert one.rooms["demo"].viewers == {} and two.rooms["demo"].performers == {}  # each where it connected
    assert two.bus is None and receiver.reader.lost == 0
    assert sender.acks > 0


@pytest.mark.slow  # servers stopped under a live stream: make test runs it
def test_a_viewer_whose_server_stops_reconnects_to_another_on_the_same_address_within_two_seconds():
    """Two servers listen on one port (as ``room --workers 2`` do); the one the viewer reached is
    stopped mid-stream, and the viewer, connecting again to the same address, reaches the other."""
    port = free_port()
    with nats_server() as url:
        rooms = [Rooms(TOKENS, pubsub=url) for _ in range(3)]
        stops = [threading.Event() for _ in rooms]

        def serve(index: int) -> None:
            with in_thread(rooms[index], port=port if index else 0, reuse_port=True) as base:
                bases[index] = base
                started[index].set()
                stops[index].wait()

        bases: list[str] = ["", "", ""]
        started = [threading.Event() for _ in rooms]
        threads = [threading.Thread(target=serve, args=(i,)) for i in range(3)]
        for thread in threads:
            thread.start()
        for event in started:
            assert event.wait(10)
        try:
            link = WebSocketLink(f"ws://127.0.0.1:{port}/r/demo", TOKENS["demo"][1], "watch")
            arrivals: list[float] = []
            with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral()), link=link) as receiver:
                sender = _performer(bases[0])  # the performer on a third server, of its own
                try:
                    held = next(i for i in (1, 2) if rooms[i].rooms["demo"].viewers)
                    frame = 0
                    for step in range(120):  # four seconds at 30 Hz; the viewer's server stops after one
                        if step == 30:
                            stops[held].set()
                            threads[held].join(10)
                        sender.write(frame / 30, standard_neutral())
                        frame += 1
                        before = receiver.reader.packets
                        receiver.wait_for_packets(before + 1, timeout=1 / 30)
                        if receiver.reader.packets > before:
                            arrivals.append(time.monotonic())
                finally:
                    sender.close()
        finally:
            for event in stops:
                event.set()
            for thread in threads:
                thread.join(10)
    other = 3 - held
    assert link.reconnects == 1 and rooms[other].rooms["demo"].forwarded > 0
    gaps = np.diff(arrivals)
    assert len(arrivals) > 80 and gaps.max() < 2.0  # back within two seconds


@pytest.mark.slow  # three Python processes start: make test runs it
def test_room_workers_share_one_port_a_killed_one_loses_its_viewers_to_the_other_and_all_stop_together(tmp_path):
    import os
    import signal
    import subprocess
    import sys
    from pathlib import Path

    port = free_port()
    with nats_server() as url:
        server = subprocess.Popen([sys.executable, "-m", "toonface", "room", "--listen", f"127.0.0.1:{port}", "--room",
                                   "demo", "--tokens", str(tmp_path / "rooms.toml"), "--workers", "2", "--pubsub", url,
                                   "--seconds", "60"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        try:
            banner = server.stdout.readline()
            assert f"room server on ws://127.0.0.1:{port}, 2 processes, rooms shared through {shown(url)}" in banner
            assert NATS_TOKEN not in banner
            lines = [server.stdout.readline() for _ in range(4)]
            perform = lines[0].rsplit("--token ", 1)[1].strip()
            watch = lines[1].rsplit("--token ", 1)[1].strip()
            base = f"ws://127.0.0.1:{port}/r/demo"
            links = [WebSocketLink(base, watch, "watch") for _ in range(12)]  # (all on one process: 1 in 4096)
            receivers = [StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral()), link=link).start()
                         for link in links]
            link = WebSocketLink(base, perform, "perform")
            sender = StreamSender((link.where, 0), StreamWriter(30.0, frames_per_packet=1, stream=7), link=link)
            try:
                for k in range(30):
                    sender.write(k / 30, standard_neutral())
                assert all(receiver.wait_for_packets(30, timeout=10) for receiver in receivers)
                children = Path(f"/proc/{server.pid}/task/{server.pid}/children").read_text().split()
                worker = next(int(pid) for pid in children  # the spawned worker (not multiprocessing's tracker)
                              if "spawn_main" in Path(f"/proc/{pid}/cmdline").read_text())
                os.kill(worker, signal.SIGKILL)  # a server killed mid-stream
                killed = time.monotonic()
                frame = 30
                while time.monotonic() - killed < 2.0:  # two seconds of frames at 30 Hz
                    sender.write(frame / 30, standard_neutral())
                    frame += 1
                    receivers[0].wait_for_packets(10**9, timeout=1 / 30)
                assert all(receiver.reader.packets >= 45 for receiver in receivers)  # each back within the two
                assert sum(link.reconnects for link in links) >= 1
                said = ""  # issue 68: a worker that died was neither restarted nor reported
                while "started again" not in said:
                    said = server.stdout.readline()
                    assert said, "the server ended without saying the worker stopped"
                assert f"worker process {worker} stopped (exit -9); started again" in said
                children = Path(f"/proc/{server.pid}/task/{server.pid}/children").read_text().split()
                assert [pid for pid in children if int(pid) != worker and "spawn_main" in Path(
                    f"/proc/{pid}/cmdline").read_text()]  # a worker again
            finally:
                sender.close()
                for receiver in receivers:
                    receiver.close()
            server.send_signal(signal.SIGTERM)  # as Ctrl-C: the workers stop with it
            assert server.wait(15) == 0
        finally:
            if server.poll() is None:
                server.kill()
                server.wait()
            server.stdout.close()
    with pytest.raises(OSError):  # nobody listens on the port any more
        socket.create_connection(("127.0.0.1", port), timeout=1).close()


@pytest.mark.parametrize("args, says", [
    (["--workers", "2"], "several workers share their rooms through --pubsub"),
    (["--workers", "2", "--pubsub", "nats://127.0.0.1:9", "--listen", "127.0.0.1:0"], "name it (not 0)"),
    (["--pubsub", "redis://127.0.0.1:6379"], "expected nats://HOST:PORT"),
    pytest.param(["--pubsub", "nats://127.0.0.1:9"], "cannot reach the NATS server at nats://127.0.0.1:9",
                 marks=pytest.mark.slow),  # (five seconds of trying)
])
def test_room_sharing_given_wrongly_is_one_line_and_a_failure(tmp_path, capsys, args, says):
    from toonface.cli import main

    code = main(["room", "--room", "demo", "--tokens", str(tmp_path / "rooms.toml"), "--seconds", "1",
                 *(["--listen", "127.0.0.1:0"] if "--listen" not in args else []), *args])
    err = capsys.readouterr().err
    assert code != 0 and says in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("workers", ["1", "2"])
def test_a_room_on_a_port_in_use_is_refused_in_a_line_and_writes_no_tokens(tmp_path, capsys, workers):
    """Issue 68: a second `room --workers 2` on a port in use started silently beside the first
    (the workers' shared port let it bind); issue 70: the tokens file was written all the same."""
    from toonface.cli import main

    with socket.socket() as taken:
        taken.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)  # as a room's workers hold it
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        code = main(["room", "--room", "demo", "--tokens", str(tmp_path / "rooms.toml"), "--seconds", "1",
                     "--listen", f"127.0.0.1:{port}", "--workers", workers, "--pubsub", "nats://127.0.0.1:9"])
    err = capsys.readouterr().err
    assert code == 2 and f"cannot listen on 127.0.0.1:{port}: Address already in use" in err
    assert len(err.strip().splitlines()) == 1 and not (tmp_path / "rooms.toml").exists()


@pytest.mark.slow  # a NATS server started and stopped: make test runs it
def test_a_room_that_loses_nats_says_so_and_stops_without_a_traceback(caplog):
    """Issue 70: a --pubsub server that lost NATS said nothing, then printed a 50-line traceback
    when stopped."""
    said: list[str] = []
    noticed = threading.Event()
    rooms = Rooms(TOKENS, pubsub="set below")
    rooms.say = lambda text: (said.append(text), noticed.set())
    with nats_server() as url:
        rooms.pubsub = url
        server = in_thread(rooms)
        server.__enter__()
    assert noticed.wait(10)  # the NATS server has stopped, and the room says so
    server.__exit__(None, None, None)  # stopped with the NATS server still away
    assert said and said[0].startswith(f"lost the NATS server at {shown(url)}: the rooms are this process's alone")
    assert rooms.bus is None and not [r for r in caplog.records if r.levelname == "ERROR"]


@pytest.mark.slow  # NATS servers started and stopped: make test runs it
def test_the_nats_server_reads_nothing_to_a_client_without_its_token_and_an_open_one_is_said():
    """Issue 68: the tutorial's NATS server took anyone, and a client with no room token read 150
    of room demo's packets in 5 s. With --auth, a client without the token is refused; a room
    server joining a NATS server that takes anyone says so."""
    def subscribe_without_token(url: str, token: str = "") -> bytes:
        """NATS's own protocol by hand: CONNECT (with ``token``, or none), SUB to every room, PING;
        what the server answers."""
        host, port = url.rsplit("@", 1)[-1].removeprefix("nats://").split(":")
        with socket.create_connection((host, int(port)), timeout=5) as raw:
            info = raw.recv(4096)
            assert b'"auth_required":true' in info
            raw.sendall(b"CONNECT " + json.dumps({"verbose": False, **({"auth_token": token} if token else {})}
                                                 ).encode() + b"\r\nSUB toonface.> 1\r\nPING\r\n")
            return raw.recv(4096)

    with nats_server() as url:
        for token in ("", "wrong-token"):
            assert b"-ERR 'Authorization Violation'" in subscribe_without_token(url, token)
        assert subscribe_without_token(url, NATS_TOKEN).startswith(b"PONG")  # (the check itself works)
    said: list[str] = []
    with nats_server(auth=False) as url:
        rooms = Rooms(TOKENS, pubsub=url)
        rooms.say = said.append
        with in_thread(rooms):
            pass
    assert any("takes clients without credentials: anyone who reaches it reads every room's packets" in s
               for s in said), said


@pytest.mark.slow  # a NATS server started and stopped: make test runs it
def test_a_shared_rooms_tokens_are_the_first_servers_on_every_server_of_it():
    """Issue 68: each server sharing a room through NATS made its own tokens, and all of them
    worked (server C's perform token performed into server A's room). The second server takes the
    first's and says so; its own work nowhere, nor does another room's token."""
    first = {"demo": ("perform-first-0123456789", "watch-first-0123456789"),
             "other": ("perform-other-0123456789", "watch-other-0123456789")}
    second = {"demo": ("perform-second-0123456789", "watch-second-0123456789"),
              "other": ("perform-other-0123456789", "watch-other-0123456789")}
    said: list[str] = []
    with nats_server() as url:
        a, b = Rooms(first, pubsub=url), Rooms(second, pubsub=url)
        b.say = said.append
        with in_thread(a), in_thread(b):
            for rooms in (a, b):
                assert isinstance(rooms.admit("demo", "perform", first["demo"][0]), type(rooms.rooms["demo"]))
                assert isinstance(rooms.admit("demo", "watch", first["demo"][1]), type(rooms.rooms["demo"]))
                assert rooms.admit("demo", "perform", second["demo"][0]) == "token"
                assert rooms.admit("demo", "perform", first["other"][0]) == "token"  # another room's
    assert said == ["room demo: the tokens of the servers already sharing it through NATS hold here too (this "
                    "server's own, in its tokens file, do not)"]


@pytest.mark.slow  # a NATS server started and stopped: make test runs it
def test_a_performer_who_leaves_one_server_is_said_to_the_viewers_of_another():
    """A departure was said to the viewers of the performer's own process only; another's pages
    waited out its two seconds of silence."""
    import aiohttp

    from stream.framing import peek_stream

    with nats_server() as url:
        a, b = Rooms(TOKENS, pubsub=url), Rooms(TOKENS, pubsub=url)
        with in_thread(a) as base_a, in_thread(b) as base_b:

            async def watch_while_one_leaves() -> tuple[list[int], list[object]]:
                watch = {"Authorization": f"Bearer {TOKENS['demo'][1]}"}
                perform = {"Authorization": f"Bearer {TOKENS['demo'][0]}"}
                async with aiohttp.ClientSession() as session, \
                        session.ws_connect(f"{base_b}/r/demo/ws?role=watch", headers=watch) as viewer:
                    writer = StreamWriter(30.0, frames_per_packet=1, stream=0x51)
                    async with session.ws_connect(f"{base_a}/r/demo/ws?role=perform", headers=perform) as one:
                        for k in range(5):
                            await one.send_bytes(writer.push(standard_neutral(), k / 30))
                        packets = [peek_stream((await viewer.receive(timeout=5)).data) for _ in range(3)]
                    said = await viewer.receive(timeout=5)  # the performer's socket closed on server A
                    while said.type == aiohttp.WSMsgType.BINARY:  # (its last packets first)
                        said = await viewer.receive(timeout=5)
                    return packets, [said.type, said.data]

            packets, said = asyncio.run(watch_while_one_leaves())
    assert set(packets) == {0x51}  # its packets came through the bus
    assert said[0] == aiohttp.WSMsgType.TEXT and json.loads(said[1]) == {"gone": [0x51]}
