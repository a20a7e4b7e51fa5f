"""A motor stream from ``toonface send`` shown in the studio: the browser viewer of a stream."""

from __future__ import annotations

import numpy as np

from stream.playout import Playout
from stream.receiver import StreamReceiver, readout


class ReceivedStream:
    """The stream received on ``address`` through a jitter buffer and concealment, as ``toonface
    receive`` does; a :class:`~toonface.studio.session.LiveSource`.

    Parameters
    ----------
    address : (host, port)
        Where to receive (UDP); port 0 picks a free one.
    neutral : ndarray, shape (21,)
        The face's rest pose (where concealment eases to when the stream stays away).
    conceal : str
        ``linear`` or ``hold`` (:class:`stream.playout.Playout`).
    jitter_ms : float
        Extra delay above what the recent packets needed.
    key : bytes, optional
        The shared secret of signed streams.
    """

    def __init__(self, address: tuple[str, int], neutral: np.ndarray, conceal: str = "linear", jitter_ms: float = 4.0,
                 key: bytes | None = None) -> None:
        self.playout = Playout(neutral, conceal, margin=jitter_ms / 1000)
        self.receiver = StreamReceiver(address, self.playout, key)
        host, port = self.receiver.address
        self.name = f"udp://{host}:{port}"

    def values(self) -> np.ndarray:
        """The motors to show now, ``(21,)``."""
        return self.receiver.values_at()[0]

    def quality(self) -> dict:
        """The readout: packets, the share lost, frames live, concealed and recovering, the median
        delay from capture to showing (ms), and the receiver's diagnosis where it has one."""
        return readout(self.receiver.summary(), self.receiver.diagnosis())

    def __enter__(self) -> ReceivedStream:
        self.receiver.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.receiver.close()
