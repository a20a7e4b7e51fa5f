"""Which names a local web server answers at, and which pages may open its WebSockets.

Shared by the studio and the room server. A page on another site can reach a server on this
machine by DNS rebinding: its own name, pointed at this machine's address, makes the browser
send ``Host: evil.example`` and ``Origin: http://evil.example``, so a server that trusted the
request's own ``Host`` would take the page as its own. The servers instead keep the names they
listen at (:func:`listen_hosts`), answer only those (:func:`host_allowed`) and open sockets only
to pages from those or from origins they were given (:func:`origin_allowed`). Listening on every
interface, any IP address of the machine is answered, but never a name that DNS could point
elsewhere unless the user names it.
"""

from __future__ import annotations

import contextlib
import ipaddress
import socket
from collections.abc import Collection
from typing import Any
from urllib.parse import urlsplit

#: Among a server's hosts: it listens on every interface and answers any IP address it is reached at.
ANY_ADDRESS = "*"
#: What a bind address of every interface is written as.
EVERY_INTERFACE = ("0.0.0.0", "::", "")


def is_loopback(host: str) -> bool:
    """Whether ``host`` (an address or a name to bind) reaches only this machine."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def listen_hosts(host: str, port: int, allow: Collection[str] = ()) -> set[str]:
    """The ``HOST:PORT`` names a server bound to ``host:port`` answers at: the address itself, and
    ``localhost``/``127.0.0.1`` where it is loopback or every interface (:data:`ANY_ADDRESS` too
    then), with ``allow``'s names (``NAME`` or ``NAME:PORT``) added.

    >>> sorted(listen_hosts("127.0.0.1", 7730))
    ['127.0.0.1:7730', 'localhost:7730']
    >>> sorted(listen_hosts("10.0.0.5", 80, ["face.example"]))
    ['10.0.0.5:80', 'face.example:80']
    """
    every = host in EVERY_INTERFACE
    shown = "127.0.0.1" if every else f"[{host}]" if ":" in host else host
    names = {f"{shown}:{port}"}
    if every or is_loopback(host):
        names |= {f"localhost:{port}", f"127.0.0.1:{port}"}
    if every:
        names.add(ANY_ADDRESS)
    return names | {name if ":" in name else f"{name}:{port}" for name in allow}


def reachable_addresses() -> list[str]:
    """This machine's IPv4 addresses that other machines may reach it at (not loopback, not
    link-local), the one its traffic leaves by first (asked of the kernel by a UDP socket
    "connected" to a documentation address: nothing is sent); empty where it has none."""
    found: list[str] = []
    with contextlib.suppress(OSError), socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        probe.connect(("192.0.2.1", 9))  # TEST-NET-1: a route is looked up, no packet leaves
        found.append(probe.getsockname()[0])
    with contextlib.suppress(OSError):
        found += [str(info[4][0]) for info in socket.getaddrinfo(socket.gethostname(), None, socket.AF_INET)]
    kept = []
    for address in found:
        ip = ipaddress.ip_address(address)
        if not (ip.is_loopback or ip.is_link_local or ip.is_unspecified) and address not in kept:
            kept.append(address)
    return kept


def host_allowed(host: str, hosts: Collection[str]) -> bool:
    """Whether a request's ``Host`` header is one the server answers: one of ``hosts``, or, where
    they hold :data:`ANY_ADDRESS`, an IP address (never a name that DNS could rebind)."""
    if host in hosts:
        return True
    if ANY_ADDRESS not in hosts:
        return False
    name = host.rsplit(":", 1)[0] if host.count(":") == 1 or host.startswith("[") else host
    try:
        ipaddress.ip_address(name.strip("[]"))
    except ValueError:
        return False
    return True


def origin_allowed(origin: str, hosts: Collection[str], origins: Collection[str] = ()) -> bool:
    """Whether a page from ``origin`` (an ``Origin`` header) may open the server's sockets: one of
    ``origins`` as given (``https://face.example``), or ``http(s)://`` and a host the server
    answers at (:func:`host_allowed`).

    >>> ours = listen_hosts("127.0.0.1", 7730)
    >>> origin_allowed("http://127.0.0.1:7730", ours), origin_allowed("http://evil.com:7730", ours)
    (True, False)
    >>> origin_allowed("https://face.example", ours, ["https://face.example"])
    True
    """
    if origin in origins:
        return True
    try:
        parts = urlsplit(origin)
        port = parts.port
    except ValueError:  # a port that is not one
        return False
    if parts.scheme not in ("http", "https") or not parts.netloc or parts.path not in ("", "/"):
        return False
    netloc = parts.netloc if port is not None else f"{parts.netloc}:{443 if parts.scheme == 'https' else 80}"
    return host_allowed(netloc, hosts) or host_allowed(parts.netloc, hosts)


def bearer_token(request: Any) -> str:
    """The token a WebSocket request (aiohttp's) carries: ``Authorization: Bearer TOKEN`` (native
    clients), or among its subprotocols, ``toonface`` and ``bearer.TOKEN`` (a page: a browser cannot
    set a socket's headers, and may not put a token in its address); "" where it has none."""
    if "Authorization" in request.headers:
        return str(request.headers["Authorization"]).removeprefix("Bearer ")
    offered = [p.strip() for p in request.headers.get("Sec-WebSocket-Protocol", "").split(",")]
    return next((p.removeprefix("bearer.") for p in offered if p.startswith("bearer.")), "")
