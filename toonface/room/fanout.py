"""One message to many WebSocket connections: its frame made once, written to each connection.

aiohttp's ``send_bytes`` frames a message anew for every connection and may wait on each; a room
sends the same packet to hundreds. The frame of a binary message from a server is its payload
behind a header of 2 to 10 bytes (RFC 6455 section 5.2: FIN and the opcode, then the length;
unmasked, uncompressed), so it is made once and handed to each connection's transport, which
keeps whole frames in order beside aiohttp's own (pings, the close). A connection with more
than :data:`LAG_BYTES` waiting to go out is skipped: a live stream drops what a slow viewer
cannot take (the stream conceals a lost packet) instead of queueing it or holding the others.
"""

from __future__ import annotations

import asyncio
import contextlib
import struct
from collections.abc import Iterable, Mapping
from typing import Any

#: A connection with more than this waiting to be sent misses messages until it drains.
LAG_BYTES = 256 * 1024
_BINARY = 0x82  # FIN, binary


def frame_of(data: bytes) -> bytes:
    """The WebSocket frame of one binary message from a server."""
    n = len(data)
    if n < 126:
        return bytes((_BINARY, n)) + data
    if n < 1 << 16:
        return struct.pack("!BBH", _BINARY, 126, n) + data
    return struct.pack("!BBQ", _BINARY, 127, n) + data


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
            if transport.get_write_buffer_size() > LAG_BYTES:
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
