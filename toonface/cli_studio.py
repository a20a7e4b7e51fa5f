"""``toonface studio``: the browser studio's local server."""

from __future__ import annotations

import asyncio

import click

from toonface.cli_options import FACE
from toonface.cli_player import _required_address


@click.command()
@click.argument("animation", required=False, type=click.Path(dir_okay=False, exists=True))
@FACE
@click.option("--listen", default="127.0.0.1:8765", show_default=True, metavar="HOST:PORT",
              help="Where the page is served. Loopback unless told otherwise; port 0 picks a free one.")
def studio(animation: str | None, face: str, listen: str) -> None:
    """The studio: a local web page showing FACE, with a slider per motor, control points to
    drag, expressions and standard motions to play, and head and eyes that can follow the
    pointer (CharToon's test mode); below it, ANIMATION (a .toml knot file; a new one
    without) on staves to edit, play, save, sample into a motor track or render to MP4
    (CharToon's Animation Editor).

    Open the printed address in a browser on this machine. The page answers only at that
    address; Ctrl-C stops the server.
    """
    from toonface.studio.server import serve
    from toonface.studio.session import StudioSession

    host, port = _required_address(listen, "--listen", 8765)
    session = StudioSession(face, animation=animation)
    try:
        asyncio.run(serve(session, host, port, lambda url: click.echo(f"studio at {url} (Ctrl-C stops)")))
    except OSError as exc:
        raise click.BadParameter(f"cannot listen on {listen}: {exc.strerror or exc}", param_hint="--listen") from None
    except KeyboardInterrupt:
        click.echo("studio stopped")


STUDIO_COMMANDS = (studio,)
