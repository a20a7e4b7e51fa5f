"""One message to many WebSocket connections: its frame made once, written to each connection.

aiohttp's ``send_bytes`` frames a message anew for every connection and may wait on each; a room
sends the same packet to hundreds. The frame of a binary message from a server is its payload
behind a header of 2 to 10 bytes (RFC 6455 section 5.2: FIN and the opcode, then the length;
unmasked, uncompressed), so it is made once and handed to each connection's transport, which
keeps whole frames in order beside aiohttp's own (pings, the close).

A live face must show the newest pose, never a queue of old ones. The kernel's send buffer of a
connection grows by itself to megabytes (Linux autotunes it: 3.9 MB on a 128 kbit/s viewer, a
minute of backlog), so each viewer's connection keeps at most :data:`UNSENT_BYTES` unsent in the
kernel (``TCP_NOTSENT_LOWAT``, :func:`keep_unsent_small`); beyond that it waits in the server,
and a connection with anything of an earlier message still waiting there is skipped
(:func:`lagging`): a slow viewer gets the newest packet (the stream conceals what it missed) or
drawing each time its link has taken the last, at the rate its link allows, never a queue.
"""

from __future__ import annotations

import asyncio
import contextlib
import socket
import struct
from collections.abc import Iterable, Mapping
from typing import Any

#: Bytes a viewer's connection may hold unsent in the kernel: 0.5 s at 64 kbit/s.
UNSENT_BYTES = 4096
_BINARY, _TEXT = 0x82, 0x81  # FIN, and the opcode


def frame_of(data: bytes, text: bool = False) -> bytes:
    """The WebSocket frame of one binary message from a server (a text message: ``data`` UTF-8)."""
    n, kind = len(data), _TEXT if text else _BINARY
    if n < 126:
        return bytes((kind, n)) + data
    if n < 1 << 16:
        return struct.pack("!BBH", kind, 126, n) + data
    return struct.pack("!BBQ", kind, 127, n) + data


def keep_unsent_small(transport: asyncio.BaseTransport | None) -> None:
    """Let the kernel hold at most :data:`UNSENT_BYTES` unsent for this connection (where the
    system has ``TCP_NOTSENT_LOWAT``: Linux, macOS); the rest waits in its transport."""
    sock = transport.get_extra_info("socket") if transport is not None else None
    option = getattr(socket, "TCP_NOTSENT_LOWAT", None)
    if sock is not None and option is not None:
        with contextlib.suppress(OSError):  # not TCP (a test's stand-in): nothing to bound
            sock.setsockopt(socket.IPPROTO_TCP, option, UNSENT_BYTES)


def lagging(transport: asyncio.WriteTransport) -> bool:
    """Whether part of an earlier message to this connection still waits in the server (its link
    has not taken what the kernel holds)."""
    return transport.get_write_buffer_size() > 0


async def send_all(sockets: Mapping[Any, asyncio.BaseTransport | None], data: bytes) -> int:
    """Send ``data`` as one binary message to each socket still open: framed once and written to
    its transport, where one is known (through ``send_bytes`` where not). Returns how many were
    skipped for lagging."""
    frame = None
    skipped = 0
    for ws, transport in list(sockets.items()):
        if ws.closed:
            continue
        if isinstance(transport, asyncio.WriteTransport):
            if transport.is_closing():
                continue
            if lagging(transport):
                skipped += 1
                continue
            frame = frame or frame_of(data)
            transport.write(frame)
            continue
        try:
            await ws.send_bytes(data)
        except ConnectionError:
            pass
    return skipped


async def say_all(sockets: Iterable[Any], text: str) -> None:
    """Send ``text`` as one text message to each of ``sockets`` still open (the room's word to
    its viewers: a performer gone); one that closes meanwhile is left."""
    for ws in list(sockets):
        if not ws.closed:
            with contextlib.suppress(ConnectionError, RuntimeError):
                await ws.send_str(text)
