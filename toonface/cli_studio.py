"""``toonface studio``: the browser studio's local server."""

from __future__ import annotations

import click

from toonface.cli_options import FACE, LIFE
from toonface.cli_player import _required_address


@click.command()
@click.argument("animation", required=False, type=click.Path(dir_okay=False, exists=True))
@FACE
@click.option("--listen", default="127.0.0.1:8765", show_default=True, metavar="HOST:PORT",
              help="Where the page is served. Loopback unless told otherwise; port 0 picks a free one.")
@click.option("--allow-host", "allow", multiple=True, metavar="NAME",
              help="Also answer requests addressed to NAME (or NAME:PORT), a name of this machine that"
                   " other machines use; repeatable. Bound to every interface the studio answers any"
                   " IP address of this machine, and a name only when given here.")
@click.option("--receive", default=None, metavar="HOST:PORT",
              help="Also receive a motor stream from `toonface send` (UDP) and show it, with its quality.")
@click.option("--conceal", default="linear", show_default=True, type=click.Choice(["hold", "linear"]),
              help="With --receive: how lost frames are guessed (as `toonface receive`).")
@LIFE
def studio(animation: str | None, face: str, listen: str, allow: tuple[str, ...], receive: str | None,
           conceal: str, life: bool | None) -> None:
    """The studio: a local web page showing FACE, with a slider per motor, control points to
    drag, expressions and standard motions to play, and head and eyes that can follow the
    pointer (CharToon's test mode); beside it, ANIMATION on staves to edit, play with a sound
    and its labels, save, sample into a motor track or render to MP4 (CharToon's Animation
    Editor). ANIMATION is a .toml knot file, a motor track (.csv, .npz) or a take to map, both
    turned into knots; without it, a new 5 s animation.

    With --receive, the page is also the browser viewer of a stream, with its latency, loss
    and concealed frames. Open the printed address in a browser on this machine. The page
    answers only at that address; Ctrl-C stops the server.

    The pages read and write files only inside the folder the studio was started in. Listening
    on an address other machines reach (--listen 0.0.0.0:8765), the printed address carries a
    secret made for this run: only a browser given it can open the page.
    """
    import asyncio
    import contextlib

    from toonface.cli_options import stream_key
    from toonface.stopping import stop_within
    from toonface.studio.live import ReceivedStream
    from toonface.studio.server import serve
    from toonface.studio.session import StudioSession

    host, port = _required_address(listen, "--listen", 8765)
    session = StudioSession(face, animation=animation, life=life)
    with contextlib.ExitStack() as stack:
        if receive is not None:
            where = _required_address(receive, "--receive", 7710)
            try:
                received = ReceivedStream(where, session.neutral, conceal, key=stream_key(None))
                session.live = stack.enter_context(received)
            except OSError as exc:
                raise click.BadParameter(f"cannot receive on {receive}: {exc.strerror or exc}",
                                         param_hint="--receive") from None
            session.show_live(True)
            click.echo(f"receiving a motor stream on {session.live.name}")
        try:
            with stop_within() as stop:  # SIGTERM ends it within seconds, a render under way too
                asyncio.run(serve(session, host, port, lambda url: _announce(url, host in ("0.0.0.0", "::", "")),
                                  allow, stop))
        except OSError as exc:
            raise click.BadParameter(f"cannot listen on {listen}: {exc.strerror or exc}",
                                     param_hint="--listen") from None
        except KeyboardInterrupt:
            click.echo("studio stopped")


def _announce(url: str, every: bool) -> None:
    click.echo(f"studio at {url} (Ctrl-C stops)")
    if every:
        click.echo("from another machine: the same address with this machine's IP address, or a name given with"
                   " --allow-host, in place of 127.0.0.1")


STUDIO_COMMANDS = (studio,)
