"""The room server's subcommand: ``toonface room`` (performers and viewers meet over WebSocket)."""

from __future__ import annotations

import asyncio
import secrets
import ssl
from pathlib import Path

import click

from common import InputError
from common.atomic import atomic_path
from toonface.cli_options import FACE, FiniteFloat
from toonface.cli_player import _required_address
from toonface.cli_stream import KEY, _key


def load_tokens(path: Path, names: tuple[str, ...]) -> dict[str, tuple[str, str]]:
    """The rooms of a tokens file (TOML: ``[rooms.NAME] perform = "..." watch = "..."``), with a
    fresh pair made and written for each of ``names`` it lacks; the file is written atomically and
    readable by its owner only."""
    import tomllib

    import tomli_w

    rooms: dict[str, tuple[str, str]] = {}
    if path.exists():
        try:
            doc = tomllib.loads(path.read_text())
            rooms = {name: (str(pair["perform"]), str(pair["watch"])) for name, pair in doc.get("rooms", {}).items()}
        except (tomllib.TOMLDecodeError, KeyError, TypeError, AttributeError) as exc:
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
@click.option("--max-viewers", default=1000, show_default=True, type=click.IntRange(1, 100_000),
              help="Viewers a room holds at once.")
@FACE
@KEY
@click.option("--seconds", default=None, type=FiniteFloat(min=0.01), help="Stop after this long.")
def room(listen: str, names: tuple[str, ...], tokens_path: str, tls_cert: str | None, tls_key: str | None,
         max_viewers: int, face: str, key_file: str | None, seconds: float | None) -> None:
    """A room server: performers (`toonface send SOURCE --to ws://HOST:PORT/r/NAME --token T`)
    and viewers (`toonface receive --from ws://HOST:PORT/r/NAME --token W`) both connect out to
    it over WebSocket, which passes NAT and firewalls; the stream's packets pass through it as
    they are (sealed end to end with --key-file). Each room has a token to perform and one to
    watch; they are printed once made and kept in --tokens.

    A browser watches at http(s)://HOST:PORT/r/NAME#watch=TOKEN (add ?obs before the # for a
    clear page for OBS's browser source): the server decodes the streams and draws the faces on
    --face for it, so it must hold the key of sealed streams (--key-file).
    """
    from aiohttp import web

    from toon import load_face
    from toonface.room.server import Rooms, make_app

    host, port = _required_address(listen, "--listen", 7730)
    path = Path(tokens_path)
    if not names and not path.exists():
        raise click.BadParameter("name a room (--room NAME), or give a tokens file that has some", param_hint="--room")
    tokens = load_tokens(path, names)
    face_obj = load_face(face)
    key = _key(key_file)
    if bool(tls_cert) != bool(tls_key):
        raise click.BadParameter("give both --tls-cert and --tls-key, or neither", param_hint="--tls-cert")
    context = None
    if tls_cert and tls_key:
        context = ssl.create_default_context(ssl.Purpose.CLIENT_AUTH)
        try:
            context.load_cert_chain(tls_cert, tls_key)
        except (ssl.SSLError, OSError) as exc:
            raise click.BadParameter(f"cannot use the certificate: {exc}", param_hint="--tls-cert") from None
    scheme = "wss" if context else "ws"

    async def serve() -> None:
        rooms = Rooms(tokens, max_viewers=max_viewers, face=face_obj, key=key)
        runner = web.AppRunner(make_app(rooms), access_log=None)  # tokens unlogged
        await runner.setup()
        site = web.TCPSite(runner, host, port, ssl_context=context, reuse_address=True)
        try:
            await site.start()
        except OSError as exc:
            await runner.cleanup()
            raise click.BadParameter(f"cannot listen on {listen}: {exc.strerror or exc}", param_hint="--listen") \
                from None
        bound = runner.addresses[0][1] if runner.addresses else port
        shown = "127.0.0.1" if host in ("0.0.0.0", "") else host
        click.echo(f"room server on {scheme}://{shown}:{bound} (Ctrl-C stops); tokens in {path}")
        for name, (perform, watch) in tokens.items():
            where = f"{scheme}://{shown}:{bound}/r/{name}"
            click.echo(f"  room {name}: perform  toonface send SOURCE --to {where} --token {perform}")
            click.echo(f"  room {name}: watch    toonface receive --from {where} --token {watch}")
            page = f"{'https' if context else 'http'}://{shown}:{bound}/r/{name}#watch={watch}"
            click.echo(f"  room {name}: browser  {page}")
            performer_page = f"{'https' if context else 'http'}://{shown}:{bound}/r/{name}/perform#perform={perform}"
            click.echo(f"  room {name}: camera   {performer_page}")
        try:
            await (asyncio.sleep(seconds) if seconds is not None else asyncio.Event().wait())
        finally:
            await runner.cleanup()

    try:
        asyncio.run(serve())
    except KeyboardInterrupt:
        pass


ROOM_COMMANDS = (room,)
