"""Type stub: the names the package loads lazily on first use (``lazy_loader``)."""

from .framing import WireError
from .packets import StreamWriter, is_key_request, key_request, read_ack
from .playout import Playout, PlayoutStats
from .reader import Frames, StreamReader
from .receiver import StreamReceiver
from .relay import FaultPlan, NetworkFaults, Relay
from .wire import quantise

__all__ = [
    "FaultPlan",
    "Frames",
    "NetworkFaults",
    "Playout",
    "PlayoutStats",
    "Relay",
    "StreamReader",
    "StreamReceiver",
    "StreamWriter",
    "WireError",
    "is_key_request",
    "key_request",
    "quantise",
    "read_ack",
]
