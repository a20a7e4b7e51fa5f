"""What the network bridges (:mod:`capture.vmc`, :mod:`capture.openseeface`) share: a UDP socket
bound at once (so a bad address fails before anything runs), its datagrams until the source is
halted, and the head they pose: the ``face`` marker set's head references, turned.

A bridge's frames carry no markers of the face, only its head references turned by the head's
rotation, so that the mapping finds the head turn as it finds a tracked face's (``head``
sources), and the tracker's scores as channels.
"""

from __future__ import annotations

import socket
import threading
from collections.abc import Iterator

import numpy as np

from capture.blendshapes import BLENDSHAPES
from capture.markerset import load_markerset
from capture.sources import Frame
from common import InputError
from common.address import parse_address

#: Bytes a bridge's socket may hold unread: a second of a sender's messages at 60 Hz with room to spare.
RECEIVE_BUFFER = 1 << 20


def listen(target: str, default_port: int, what: str, timeout: float) -> socket.socket:
    """A UDP socket bound to ``target`` (``HOST:PORT``, ``PORT``; loopback by default), waking
    every ``timeout`` seconds; an :class:`InputError` naming ``what`` where it cannot be."""
    try:
        host, port = parse_address(target, default_port)
    except ValueError as exc:
        raise InputError(f"{what}: {exc}") from None
    sock = socket.socket(socket.AF_INET6 if ":" in host else socket.AF_INET, socket.SOCK_DGRAM)
    try:
        sock.bind((host, port))
    except OSError as exc:
        sock.close()
        raise InputError(f"cannot listen for {what} on {host}:{port}: {exc.strerror or exc}") from None
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, RECEIVE_BUFFER)  # a burst of messages is not lost
    sock.settimeout(timeout)
    return sock


def address_of(sock: socket.socket) -> str:
    """``HOST:PORT`` where ``sock`` listens (the port a port 0 found)."""
    host, port = sock.getsockname()[:2]
    return f"{host}:{port}"


def datagrams(sock: socket.socket, halt: threading.Event) -> Iterator[bytes]:
    """The datagrams ``sock`` receives until ``halt`` is set (looked at each time the socket's
    timeout passes); the socket is closed when they end."""
    try:
        while not halt.is_set():
            try:
                yield sock.recv(65536)
            except TimeoutError:
                continue
    finally:
        sock.close()


def head_references() -> tuple[tuple[str, ...], np.ndarray]:
    """The labels of the ``face`` marker set's head references and their rest ``(R, 3)``, mm."""
    markerset = load_markerset("face")
    labels = markerset.head_reference
    return labels, np.array([markerset.neutral_of(label) for label in labels])


def posed(t: float, rest: np.ndarray, turn: np.ndarray | None, scores: np.ndarray,
          confidence: float | None = None) -> Frame:
    """A bridge's frame at ``t``: the head references ``rest`` turned by ``turn`` ``(3, 3)`` (held
    still where None), which is the frame's head, and the ARKit ``scores`` ``(51,)``."""
    turn = np.eye(3) if turn is None else turn
    return Frame(t, rest @ turn.T, scores, confidence, turn)


def lost(t: float, rest: np.ndarray) -> Frame:
    """A frame in which the tracker has lost the performer: nothing seen, nothing sure."""
    return Frame(t, np.full(rest.shape, np.nan), np.full(len(BLENDSHAPES), np.nan), 0.0)
