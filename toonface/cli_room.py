"""The room server's subcommand: ``toonface room`` (performers and viewers meet over WebSocket)."""

from __future__ import annotations

import asyncio
import dataclasses
import multiprocessing
import os
import secrets
import socket
import ssl
from pathlib import Path
from typing import Any

import click

from common import InputError
from common.atomic import atomic_path
from common.limits import read_regular_text
from toonface.cli_options import FACE, KEY, FiniteFloat, stream_key
from toonface.cli_player import _required_address
from toonface.room.pubsub import shown as uncredentialed
from toonface.stopping import stop_within


def load_tokens(path: Path, names: tuple[str, ...]) -> dict[str, tuple[str, str]]:
    """The rooms of a tokens file (TOML: ``[rooms.NAME] perform = "..." watch = "..."``), with a
    fresh pair made and written for each of ``names`` it lacks; the file is written atomically and
    readable by its owner only."""
    import tomllib

    import tomli_w

    rooms: dict[str, tuple[str, str]] = {}
    if path.exists():
        try:
            doc = tomllib.loads(read_regular_text(path, what="tokens file"))
            rooms = {name: (str(pair["perform"]), str(pair["watch"])) for name, pair in doc.get("rooms", {}).items()}
        except (InputError, tomllib.TOMLDecodeError, KeyError, TypeError, AttributeError) as exc:
            raise click.BadParameter(f"{path}: not a tokens file ({exc})", param_hint="--tokens") from None
    fresh = [name for name in names if name not in rooms]
    for name in fresh:
        rooms[name] = (secrets.token_urlsafe(18), secrets.token_urlsafe(18))
    if fresh or not path.exists():
        try:
            with atomic_path(path, mode=0o600) as temporary:  # owner-only from the start: it holds secrets
                temporary.write_text(tomli_w.dumps({"rooms": {n: {"perform": p, "watch": w}
                                                              for n, (p, w) in rooms.items()}}))
        except InputError as exc:
            raise click.BadParameter(str(exc), param_hint="--tokens") from None
    return rooms


@click.command()
@click.option("--listen", default="127.0.0.1:7730", show_default=True, metavar="HOST:PORT",
              help="Where performers and viewers connect (0.0.0.0 for other machines; put it behind a TLS "
                   "proxy, or give --tls-cert and --tls-key).")
@click.option("--room", "names", multiple=True, metavar="NAME",
              help="A room to open (again for more); its tokens are made once and kept in --tokens.")
@click.option("--tokens", "tokens_path", default="rooms.toml", show_default=True, type=click.Path(dir_okay=False),
              help="The rooms' tokens (TOML, readable by you only), kept across restarts.")
@click.option("--tls-cert", default=None, type=click.Path(dir_okay=False, exists=True), help="Serve wss:// with this "
              "certificate (PEM)...")
@click.option("--tls-key", default=None, type=click.Path(dir_okay=False, exists=True), help="...and its key.")
@click.option("--tls-self-signed", is_flag=True,
              help="Serve https:// and wss:// with a certificate of the server's own for the addresses it is reached "
                   "at (a phone on the LAN needs https to use its camera), kept beside --tokens and printed with its "
                   "SHA-256 fingerprint: check it in the browser's warning before accepting.")
@click.option("--max-viewers", default=1000, show_default=True, type=click.IntRange(1, 100_000),
              help="Viewers a room holds at once.")
@FACE
@KEY
@click.option("--pubsub", default=None, metavar="nats://TOKEN@HOST:PORT", envvar="TOONFACE_PUBSUB",
              help="Share the rooms with every other room server connected to this NATS server (other processes, "
                   "other machines): a viewer on any of them sees a performer on any. Start NATS with --auth TOKEN "
                   "and give the token here (or in $TOONFACE_PUBSUB, kept out of the process list): a NATS server "
                   "that takes anyone lets anyone read every room's packets, and the room says so.")
@click.option("--workers", default=1, show_default=True, type=click.IntRange(1, 64),
              help="Server processes on --listen's port (the system spreads connections over them; a viewer whose "
                   "process stops reconnects to another, and the process is started again): one per core. More "
                   "than one needs --pubsub.")
@click.option("--allow-origin", "origins", multiple=True, metavar="URL",
              help="Also let pages from this origin (https://NAME[:PORT], the address a TLS proxy serves the "
                   "rooms at) open the rooms' sockets; repeatable. Pages of the address the server listens at "
                   "always may (any IP address of this machine under 0.0.0.0); pages of other sites never.")
@click.option("--stats", default=None, type=FiniteFloat(min=0.1), metavar="SECONDS",
              help="Every SECONDS (60 is a minute), a line of what each room did: performers and viewers now, packets "
                   "relayed and missed by slow viewers, refusals by reason.")
@click.option("--seconds", default=None, type=FiniteFloat(min=0.01), help="Stop after this long.")
def room(listen: str, names: tuple[str, ...], tokens_path: str, tls_cert: str | None, tls_key: str | None,
         tls_self_signed: bool, max_viewers: int, face: str, key_file: str | None, pubsub: str | None, workers: int,
         origins: tuple[str, ...], stats: float | None, seconds: float | None) -> None:
    """A room server: performers (`toonface send SOURCE --to ws://HOST:PORT/r/NAME --token T`)
    and viewers (`toonface receive --from ws://HOST:PORT/r/NAME --token W`) both connect out to
    it over WebSocket, which passes NAT and firewalls; the stream's packets pass through it as
    they are (sealed end to end where send and receive share a --key-file). Each room has a
    token to perform and one to watch; they are printed once made and kept in --tokens.

    A browser watches at http(s)://HOST:PORT/r/NAME#watch=TOKEN (add ?obs before the # for a
    clear page for OBS's browser source): the page is sent the packets and draws the faces on
    --face itself; a sealed stream opens there with &key=KEY added to the link (send --key-file
    prints it), and the server needs no key. With ?draw=server the server draws the faces for the
    page instead, at hundreds of kbit/s, and must hold the key of sealed streams (--key-file). A
    browser performs from its camera at http(s)://HOST:PORT/r/NAME/perform#perform=TOKEN.
    """
    from toon import load_face

    host, port = _required_address(listen, "--listen", 7730)
    path = Path(tokens_path)
    if not names and not path.exists():
        raise click.BadParameter("name a room (--room NAME), or give a tokens file that has some", param_hint="--room")
    if workers > 1 and not pubsub:
        raise click.BadParameter("several workers share their rooms through --pubsub nats://HOST:PORT",
                                 param_hint="--workers")
    if workers > 1 and port == 0:
        raise click.BadParameter("several workers share one port: name it (not 0)", param_hint="--listen")
    if pubsub is not None and not pubsub.startswith(("nats://", "tls://")):
        raise click.BadParameter(f"{uncredentialed(pubsub)}: expected nats://HOST:PORT", param_hint="--pubsub")
    _check_port(host, port)  # before the tokens file is written, and before workers share the port
    tokens = load_tokens(path, names)
    load_face(face)  # (an error now, not in each worker)
    if bool(tls_cert) != bool(tls_key):
        raise click.BadParameter("give both --tls-cert and --tls-key, or neither", param_hint="--tls-cert")
    if tls_self_signed:
        if tls_cert:
            raise click.BadParameter("give --tls-cert and --tls-key, or --tls-self-signed",
                                     param_hint="--tls-self-signed")
        tls_cert, tls_key = _own_certificate(host, path)
    if tls_cert and tls_key:
        _tls(tls_cert, tls_key)
    for origin in origins:
        if not origin.startswith(("http://", "https://")) or origin.rstrip("/").count("/") != 2:
            raise click.BadParameter(f"{origin}: expected an origin, http(s)://NAME[:PORT]",
                                     param_hint="--allow-origin")
    settings = Settings(host, port, tokens, max_viewers, face, stream_key(key_file), tls_cert, tls_key, pubsub,
                        workers > 1, seconds, tuple(o.rstrip("/") for o in origins), stats)
    spawn = multiprocessing.get_context("spawn")
    readies = [spawn.Event() for _ in range(workers - 1)]
    others = [spawn.Process(target=_worker, args=(settings, ready), daemon=True) for ready in readies]
    try:
        with stop_within():  # SIGTERM ends it within seconds, even with a page's mapper busy
            asyncio.run(_serve(settings, path, list(zip(others, readies, strict=True))))
    except KeyboardInterrupt:
        pass
    finally:
        for process in others:
            if process.is_alive():
                process.terminate()
            process.join(5)


@dataclasses.dataclass(frozen=True)
class Settings:
    """What each room server process is to serve (picklable: a worker process gets a copy)."""

    host: str
    port: int
    tokens: dict[str, tuple[str, str]]
    max_viewers: int
    face: str
    key: bytes | None
    tls_cert: str | None
    tls_key: str | None
    pubsub: str | None
    shared_port: bool
    seconds: float | None
    origins: tuple[str, ...] = ()
    stats: float | None = None  # seconds between counter lines (--stats)


def _check_port(host: str, port: int) -> None:
    """A usage error where something already listens at ``host:port``: bound alone (without
    SO_REUSEPORT, which the workers share the port with), a port in use is refused, so a second
    ``room --workers 2`` there does not start silently beside the first."""
    if port == 0:
        return
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # (a closed connection's wait is no user)
        try:
            probe.bind((host or "0.0.0.0", port))
        except OSError as exc:
            raise click.BadParameter(f"cannot listen on {host}:{port}: {exc.strerror or exc} (another server there?)",
                                     param_hint="--listen") from None


def _own_certificate(host: str, tokens: Path) -> tuple[str, str]:
    """``--tls-self-signed``: the certificate kept beside the tokens file, made anew where it does
    not name an address the server is reached at (:mod:`toonface.self_signed`), and said."""
    from toonface.self_signed import paths_beside, self_signed
    from toonface.web_hosts import EVERY_INTERFACE, reachable_addresses

    addresses = reachable_addresses() if host in EVERY_INTERFACE else [host]
    try:
        made = self_signed(*paths_beside(tokens), addresses)
    except InputError as exc:
        raise click.BadParameter(str(exc), param_hint="--tls-self-signed") from None
    click.echo(f"certificate {made.cert} ({'made' if made.made else 'kept'}, self-signed for "
               f"{', '.join(made.addresses)}): a browser warns once; accept it where its certificate's SHA-256 "
               f"fingerprint reads {made.fingerprint}")
    return str(made.cert), str(made.key)


def _tls(cert: str, key: str) -> ssl.SSLContext:
    context = ssl.create_default_context(ssl.Purpose.CLIENT_AUTH)
    try:
        context.load_cert_chain(cert, key)
    except (ssl.SSLError, OSError) as exc:
        raise click.BadParameter(f"cannot use the certificate: {exc}", param_hint="--tls-cert") from None
    return context


def _worker(settings: Settings, ready: Any) -> None:
    """A further server process (``--workers``): serves until stopped, ``ready`` (an Event) set
    once it listens."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the parent stops it (Ctrl-C reaches the whole group)
    try:
        asyncio.run(_serve(settings, None, [], ready))
    except click.ClickException as exc:
        exc.show()
        raise SystemExit(1) from None


async def _serve(settings: Settings, path: Path | None, others: list[tuple[Any, Any]], ready: Any = None) -> None:
    """Serve the rooms in this process (announcing them where ``path``, the tokens file, is given,
    once ``others``, the further workers and their readiness events, are started and listening
    too; ``ready`` is set once this one listens)."""
    from aiohttp import web

    from toon import load_face
    from toonface.room.server import Rooms, make_runner
    from toonface.web_hosts import EVERY_INTERFACE, listen_hosts, reachable_addresses

    s = settings
    context = _tls(s.tls_cert, s.tls_key) if s.tls_cert and s.tls_key else None
    scheme = "wss" if context else "ws"
    rooms = Rooms(s.tokens, max_viewers=s.max_viewers, face=load_face(s.face), key=s.key, pubsub=s.pubsub,
                  origins=s.origins)
    rooms.say = lambda text: click.echo(f"toonface: warning: {text}", err=True)
    runner = make_runner(rooms)
    try:
        await runner.setup()
    except ConnectionError as exc:  # the NATS server
        raise click.ClickException(str(exc)) from None
    site = web.TCPSite(runner, s.host, s.port, ssl_context=context, reuse_address=True, reuse_port=s.shared_port)
    try:
        await site.start()
    except OSError as exc:
        await runner.cleanup()
        raise click.BadParameter(f"cannot listen on {s.host}:{s.port}: {exc.strerror or exc}",
                                 param_hint="--listen") from None
    rooms.hosts |= listen_hosts(s.host, runner.addresses[0][1] if runner.addresses else s.port)
    if ready is not None:
        ready.set()
    for process, _ in others:
        process.start()
    loop = asyncio.get_running_loop()
    for process, started in others:
        while not await loop.run_in_executor(None, started.wait, 0.5):
            if process.exitcode is not None:
                await runner.cleanup()
                raise click.ClickException(f"a worker process stopped before it listened (exit {process.exitcode})")
    if path is not None:
        bound = runner.addresses[0][1] if runner.addresses else s.port
        reachable = reachable_addresses() if s.host in EVERY_INTERFACE else []
        shown = reachable[0] if reachable else "127.0.0.1" if s.host in EVERY_INTERFACE else s.host
        shared = f", {len(others) + 1} processes" if others else ""
        shared += f", rooms shared through {uncredentialed(s.pubsub)}" if s.pubsub else ""
        click.echo(f"room server on {scheme}://{shown}:{bound}{shared} (Ctrl-C stops); tokens in {path}")
        if s.host in EVERY_INTERFACE:  # the links name the address other machines reach this one at
            also = ", ".join([*reachable[1:], "127.0.0.1 from this machine"])
            click.echo(f"  every interface: also at {also}" if reachable
                       else "  every interface, but no address other machines reach was found: 127.0.0.1 only")
        web_scheme = "https" if context else "http"
        for name, room in rooms.rooms.items():  # (a shared room's tokens as agreed: Bus.agree)
            perform, watch = room.perform_token, room.watch_token
            where = f"{scheme}://{shown}:{bound}/r/{name}"
            click.echo(f"  room {name}: perform  toonface send SOURCE --to {where} --token {perform}")
            click.echo(f"  room {name}: watch    toonface receive --from {where} --token {watch}")
            click.echo(f"  room {name}: browser  {web_scheme}://{shown}:{bound}/r/{name}#watch={watch}")
            click.echo(f"  room {name}: camera   {web_scheme}://{shown}:{bound}/r/{name}/perform#perform={perform}")
    watcher = asyncio.create_task(_watch(s, others, rooms)) if others or s.stats else None
    try:
        await (asyncio.sleep(s.seconds) if s.seconds is not None else asyncio.Event().wait())
    finally:
        if watcher is not None:
            watcher.cancel()
        await runner.cleanup()


async def _watch(settings: Settings, others: list[tuple[Any, Any]], rooms: Any) -> None:
    """Start again a worker process that stopped (said), and with ``--stats`` say what this
    process did every so many seconds (:mod:`toonface.room.counters`)."""
    from toonface.room.counters import Counters

    counters, loop = Counters(), asyncio.get_running_loop()
    due = loop.time() + (settings.stats or 0.0)
    who = f"process {os.getpid()}: " if settings.shared_port else ""
    while True:
        await asyncio.sleep(min(1.0, settings.stats or 1.0))
        for k, (process, _) in enumerate(others):
            if process.exitcode is not None:
                click.echo(f"toonface: warning: worker process {process.pid} stopped (exit {process.exitcode}); "
                           "started again", err=True)
                ready = multiprocessing.get_context("spawn").Event()
                others[k] = (multiprocessing.get_context("spawn").Process(target=_worker, args=(settings, ready),
                                                                          daemon=True), ready)
                others[k][0].start()
        if settings.stats and loop.time() >= due:
            click.echo(f"{who}{counters.line(rooms)}")
            due += settings.stats


ROOM_COMMANDS = (room,)
