"""Telepresence subcommands: send (performer end), receive (viewer end), relay (a bad network)."""

from __future__ import annotations

import base64
import json
import secrets
import threading
import time
from collections.abc import Callable
from typing import Any

import click

from toonface.cli_options import (
    BACKGROUND,
    EYE_CONTACT,
    FACE,
    FORCE_RECORD,
    KEY,
    LIFE,
    LIVE_HOLD_GAP,
    LIVE_MAX_GAP,
    NO_PHYSICS,
    OPENSEEFACE,
    SIZE,
    VIRTUAL_CAMERA,
    VMC,
    VMC_OUT,
    FiniteFloat,
    TakeReading,
    bridge_spec,
    check_output,
    fresh_recording,
    parse_size,
    read_take,
    stream_key,
    take_options,
    with_background,
    without_physics,
)
from toonface.cli_player import _address, _required_address

ROOM_TOKEN = click.option("--token", default=None, envvar="TOONFACE_ROOM_TOKEN",
                          help="A room's token (to perform, for send; to watch, for receive), as toonface room "
                               "prints it. Or set TOONFACE_ROOM_TOKEN.")
ROOM_CA = click.option("--ca-file", default=None, type=click.Path(dir_okay=False, exists=True),
                       envvar="TOONFACE_ROOM_CA",
                       help="For a wss:// room server with its own (self-signed) certificate: that certificate (PEM), "
                            "trusted beside the system's.")
OPEN_STREAM = ("toonface: note: the stream is not encrypted: anyone on the path can read it and send as a "
               "performer; give both ends the same --key-file (or TOONFACE_STREAM_KEY) to seal it")


def _warn(text: str) -> None:
    click.echo(f"toonface: warning: {text}", err=True)


def page_key(key: bytes) -> str:
    """``key`` as the viewer page reads it from its link's fragment: base64url, unpadded."""
    return base64.urlsafe_b64encode(key).decode("ascii").rstrip("=")


@click.command()
@click.argument("source", required=False)
@VMC
@OPENSEEFACE
@click.option("--to", "targets", required=True, multiple=True, metavar="HOST:PORT|ws://HOST:PORT/r/ROOM",
              help="Where the receiver (or a relay) listens, or a room server's room (with --token); give it again "
                   "to send to several (each its own stream of the same frames).")
@ROOM_TOKEN
@ROOM_CA
@click.option("--mapping", default=None, metavar="NAME|FILE",
              help="Mapping [default: the preset matching the markers].")
@click.option("--profile", "profile_path", default=None, type=click.Path(dir_okay=False),
              help="Performer profile, a file or a built-in's name [default: the marker set's typical one, rest from "
                   "the first second].")
@click.option("--seconds", default=None, type=FiniteFloat(min=0.1), help="Stop after this long.")
@click.option("--loop", "--repeat", "repeat", is_flag=True,
              help="A take file or a video (also played as a camera): play it again and again.")
@click.option("--frames-per-packet", default=2, show_default=True, type=click.IntRange(1, 32),
              help="More: fewer packets and headers, more delay.")
@click.option("--keyframe-seconds", default=0.5, show_default=True, type=FiniteFloat(0.02, 0.5),
              help="A keyframe at least this often (also whenever the receiver asks).")
@click.option("--colour", default="blue", show_default=True, help="A video: the dot markers' colour.")
@KEY
@click.option("--record", default=None, type=click.Path(dir_okay=False), help="Also write the motors sent (.csv/.npz).")
@FORCE_RECORD
@click.option("--save-profile", default=None, type=click.Path(dir_okay=False),
              help="At the end, write the profile used (with ranges learned live, for a camera) to reuse with "
                   "--profile next time (.toml).")
@click.option("--stats", is_flag=True, help="Print bit rates and the mapping's cost per frame at the end.")
@LIVE_MAX_GAP
@LIVE_HOLD_GAP
@click.option("--id", "stream_id", default=None, type=click.IntRange(0, 65535),
              help="This performer's stream id, for a receiver showing several [default: a random one].")
@EYE_CONTACT
@LIFE
@take_options
def send(source: str | None, vmc: str | None, openseeface: str | None, targets: tuple[str, ...], token: str | None,
         ca_file: str | None, mapping: str | None,
         profile_path: str | None, seconds: float | None, repeat: bool, frames_per_packet: int,
         keyframe_seconds: float, colour: str, key_file: str | None, record: str | None, save_profile: str | None,
         stats: bool, max_gap: float, hold_gap: float, stream_id: int | None, eye_contact: bool, life: bool | None,
         force: bool, reading: TakeReading) -> None:
    """Stream a performer's face as motor values: SOURCE is a take file (played in real time),
    a video with dot markers (tracked as it plays), camera:N, `synthetic` (the synthetic
    performer), or instead --vmc HOST:PORT (a face-tracking app over the VMC protocol) or
    --openseeface HOST:PORT (OpenSeeFace's tracker).

    Cleaning and mapping run live at this end; only the 21 motor values cross the network,
    about 2.5 kbit/s of coded payload at 60 Hz. The receiver chooses the face.
    """
    from capture.sources import open_source
    from mapping import load_profile
    from mapping import save_profile as write_profile
    from mapping.eye_contact import LiveEyeContact
    from toonface.outputs import Outputs
    from toonface.send import SendReport, build_mapper, run_sender

    addresses = [(target, 0) if target.startswith(("ws://", "wss://")) else _required_address(target, "--to", 7710)
                 for target in targets]
    if len(set(addresses)) < len(addresses):
        raise click.BadParameter("the same address twice", param_hint="--to")
    check_output(record, "--record")
    check_output(save_profile, "--save-profile")
    record = fresh_recording(record, force, lambda text: click.echo(f"toonface: note: {text}", err=True))
    spec = bridge_spec(source, vmc, openseeface)
    assert spec is not None
    src = open_source(spec, read_take=lambda path: read_take(path, reading), repeat=repeat, colour=colour,
                      seconds=seconds)
    notes: list[str] = []
    mapper = build_mapper(src, mapping, load_profile(profile_path) if profile_path else None, notes=notes, life=life,
                          regress_seconds=max_gap, hold_seconds=hold_gap)
    for note in notes:
        click.echo(f"note: {note}", err=True)
    if eye_contact:
        mapper.eye_contact = LiveEyeContact(mapper.neutral, after=0.0, say=lambda text: click.echo(f"note: {text}"))
    key = stream_key(key_file)
    if key is None:
        click.echo(OPEN_STREAM, err=True)
    with Outputs() as outputs:
        if stream_id is None:
            stream_id = secrets.randbelow(0x10000)
        streams = [outputs.motor(host if port == 0 else f"udp://{host}:{port}", rate=src.rate, key=key,
                                 frames_per_packet=frames_per_packet, keyframe_seconds=keyframe_seconds,
                                 stream=stream_id, say=_warn, token=token or "", ca_file=ca_file)
                   for host, port in addresses]
        recording = outputs.motor(record, rate=src.rate) if record else None
        where = ", ".join(host if port == 0 else f"{host}:{port}" for host, port in addresses)
        click.echo(f"sending {src.name} at {src.rate:g} Hz to {where} as stream {stream_id} (Ctrl-C stops)")
        if key is not None and any(port == 0 for _, port in addresses):  # a room: its pages open the seal themselves
            click.echo(f"sealed: a browser opens it with the room's page link, ?draw=page before the # and "
                       f"&key={page_key(key)} after the watch token (the room server never sees the key)")
        report = SendReport()
        try:
            run_sender(src, mapper, outputs.motors, seconds, report=report)
        except KeyboardInterrupt:
            click.echo("stopped", err=True)
    if recording is not None and recording.written is not None:
        click.echo(f"wrote {recording.written}")
    if save_profile and mapper.ready:
        click.echo(f"wrote {write_profile(mapper.profile, save_profile)}")
    elif save_profile:
        click.echo(f"toonface: warning: no profile written to {save_profile}: the stream ended during its rest",
                   err=True)
    for (host, port), stream in zip(addresses, streams, strict=True):
        rates = stream.rates(report.frames)
        click.echo(f"sent {rates['frames']} frames in {rates['packets']} packets to "
                   f"{host if port == 0 else f'{host}:{port}'}: payload "
                   f"{rates['payload_kbps']} kbit/s, wire {rates['wire_kbps']} kbit/s")
        if stats:
            click.echo(json.dumps({**rates, **report.cost()}))


@click.command()
@click.option("--listen", default="127.0.0.1:7710", show_default=True, metavar="HOST:PORT",
              help="UDP address to receive on (0.0.0.0 to accept other machines).")
@click.option("--from", "room_url", default=None, metavar="ws://HOST:PORT/r/ROOM",
              help="Watch a room on a room server (toonface room) instead of listening for UDP: the connection goes "
                   "out, through NAT and firewalls. With --token.")
@ROOM_TOKEN
@ROOM_CA
@FACE
@SIZE
@BACKGROUND
@VIRTUAL_CAMERA
@click.option("-o", "--output", default=None, type=click.Path(),
              help="Record: a .mp4 file, a folder for PNG frames, or - for raw RGB on standard output.")
@click.option("--preview", default=None, metavar="HOST:PORT", help="Serve a live MJPEG preview, e.g. 127.0.0.1:8080.")
@click.option("--fps", default=60.0, show_default=True, type=FiniteFloat(1, 240), help="Frames drawn a second.")
@click.option("--conceal", default="linear", show_default=True, type=click.Choice(["hold", "linear"]),
              help="How lost frames are guessed (then eased to neutral if the loss goes on); linear "
                   "had the lower error on the live performer and on real takes under loss.")
@click.option("--jitter-ms", default=4.0, show_default=True, type=FiniteFloat(0, 500),
              help="Extra delay above what the recent packets needed.")
@click.option("--max-jump", default=0.05, show_default=True, type=FiniteFloat(0.001, 1),
              help="While concealing and recovering, the most a motor moves per stream frame where its "
                   "own recent steps were smaller.")
@click.option("--seconds", default=None, type=FiniteFloat(min=0.1), help="Stop after this long.")
@KEY
@click.option("--record", default=None, type=click.Path(dir_okay=False),
              help="Also write the motors shown (.csv/.npz), at stream time: row k is the sender's frame k "
                   "(from its start, when this end saw it); each later performer's beside it, as STEM-2.EXT, "
                   "STEM-3.EXT... in the order they came.")
@FORCE_RECORD
@click.option("--stats", is_flag=True, help="Print packets, loss, drops, concealment and latency each second.")
@VMC_OUT
@click.option("--performers", "performers_path", default=None, type=click.Path(dir_okay=False),
              help="Where several performers sit and on which faces (toonface.performers/1 TOML) [default: each "
                   "sender that comes takes the next cell of a grid, on --face].")
@click.option("--max-performers", default=8, show_default=True, type=click.IntRange(1, 64),
              help="Senders shown at once (each with its own stream id); 1: the first only.")
@NO_PHYSICS
def receive(listen: str, room_url: str | None, token: str | None, ca_file: str | None, face: str, size: str,
            output: str | None, preview: str | None, fps: float, conceal: str, jitter_ms: float, max_jump: float,
            seconds: float | None, key_file: str | None, record: str | None, stats: bool, vmc_out: str | None,
            performers_path: str | None, max_performers: int, no_physics: bool, force: bool, background: str | None,
            virtual_camera: bool) -> None:
    """Show a motor stream from `toonface send` on a face of this end's choosing.

    A jitter buffer absorbs late packets; lost ones are concealed, and when the stream comes
    back a motor catches up no faster than --max-jump per frame or its own recent fastest step.
    Bad packets (oversized, malformed, replayed, or not sealed with --key-file's key) are dropped
    and counted; packets that do not open for a second are said at once. Several senders (each
    `send --id`) are shown together, each on its own face; one that goes quiet passes to an idle
    face, then fades out, and the others go on. --vmc-out
    carries the first performer's motors (a VMC receiver drives one avatar).
    """
    from player.ensemble import Ensemble, load_seats
    from player.live import ListenError, LiveSettings, run_live
    from stream.playout import Playout
    from stream.receiver import StreamReceiver
    from toon import load_face
    from toon.motors import N_MOTORS
    from toonface.outputs import Outputs, PerformerRecordings

    check_output(record, "--record")
    face_obj = with_background(without_physics(load_face(face), no_physics), background)
    dims = parse_size(size)
    say = (lambda text: click.echo(text, err=True)) if output == "-" else click.echo
    record = fresh_recording(record, force, lambda text: click.echo(f"toonface: note: {text}", err=True))
    seats = load_seats(performers_path) if performers_path else []

    recordings: PerformerRecordings | None = None

    def fresh() -> Playout:
        return Playout(face_obj.neutral(), conceal, margin=jitter_ms / 1000, max_jump=max_jump,
                       declared=face_obj.extra_neutral())

    def playout_for() -> Playout:  # each newcomer's, recorded where asked
        made = fresh()
        if recordings is not None:
            recordings.attach(made)
        return made

    playout = fresh()
    key = stream_key(key_file)
    link = None
    if room_url is not None:
        from stream.websocket import LinkError, WebSocketLink

        try:
            link = WebSocketLink(room_url, token or "", "watch", ca_file=ca_file)
        except LinkError as exc:
            raise click.BadParameter(str(exc), param_hint="--from") from None
    try:
        receiver = StreamReceiver(_required_address(listen, "--listen", 7710), playout, key,
                                  more=playout_for if max_performers > 1 else None, max_streams=max_performers,
                                  say=_warn, link=link)
    except OSError as exc:
        raise click.BadParameter(f"cannot listen on {listen}: {exc.strerror or exc}", param_hint="--listen") from None
    if key is None:
        click.echo(OPEN_STREAM, err=True)
    with receiver, Outputs() as outputs:
        settings = LiveSettings(loop_time=1 / fps, size=dims, tcp=None, preview=_address(preview, "--preview", 8080),
                                seconds=seconds)
        if output is not None:
            settings.sinks.append(outputs.picture(output, rate=fps, size=dims, live=True,
                                                  background=face_obj.background))
        if virtual_camera:
            settings.sinks.append(outputs.picture("vcam:", rate=fps, size=dims, background=face_obj.background))
        if record:  # each performer's stream frames at stream time, as shown
            recordings = PerformerRecordings(outputs, record)
            recordings.attach(playout, first=True)
        if vmc_out is not None:
            settings.shown.append(outputs.motor(f"vmc://{vmc_out}", neutral=face_obj.neutral()).write)
        settings.source = lambda t: receiver.values_at()[0][:N_MOTORS]
        settings.extra = lambda t: receiver.extra_shown()  # of the row the line above just took
        settings.say = lambda text: click.echo(f"toonface: warning: {text}", err=True)
        ensemble: Ensemble | None = None
        if max_performers > 1:
            ensemble = Ensemble(face_obj, dims, settings.providers, seats, say=_warn)
            looked: dict[str, Any] = {}

            def rows(t: float) -> list:  # one look a frame: each look counts a frame shown (--stats)
                if looked.get("t") != t:
                    looked["t"], looked["rows"] = t, receiver.performers()
                return looked["rows"]
            settings.source = lambda t: rows(t)[0][1] if rows(t) else receiver.values_at()[0][:N_MOTORS]
            settings.extra = lambda t: rows(t)[0][3] if rows(t) and len(rows(t)[0]) > 3 else {}
            settings.scene = lambda t: ensemble.frame(rows(t), t)
        done = threading.Event()

        def summary() -> dict:
            counters = receiver.summary()
            if ensemble is not None and ensemble.hidden:
                counters["hidden"] = sorted(ensemble.hidden)  # came, and have no seat
            return counters
        if stats:
            threading.Thread(target=_print_stats, args=(summary, done, say), daemon=True).start()

        def ready(addresses: dict[str, str]) -> None:
            host, port = receiver.address
            where = f"room {room_url}" if link is not None else f"{host}:{port}"
            say(f"receiving on {where}, showing {face_obj.name} at {fps:g} fps (Ctrl-C stops)")
            for kind, where in addresses.items():
                say(f"{kind} {where}")
        try:
            report = run_live(face_obj, settings, ready)
        except ListenError as exc:
            raise click.BadParameter(str(exc), param_hint="--preview") from None
        finally:
            done.set()
    for written in recordings.written() if recordings is not None else []:  # kept however the run ends
        say(f"wrote {written}")
    if (dropped := report.summary(1 / fps)) is not None:
        say(dropped)
    if (why := receiver.diagnosis()) is not None:
        click.echo(f"toonface: warning: {why}", err=True)
    say(json.dumps(summary()))


def _print_stats(summary: Callable[[], dict], done: threading.Event, say: Callable[[str], None]) -> None:
    while not done.wait(1.0):
        say(json.dumps(summary()))


@click.command()
@click.option("--listen", default="127.0.0.1:7711", show_default=True, metavar="HOST:PORT", help="Where senders send.")
@click.option("--to", "target", required=True, metavar="HOST:PORT", help="Where to forward (the receiver).")
@click.option("--loss", default=0.0, show_default=True, type=FiniteFloat(0, 1), help="Probability of a loss.")
@click.option("--burst-ms", default=0.0, show_default=True, type=FiniteFloat(0, 10000),
              help="Loss bursts this long, about one every 2 s.")
@click.option("--duplicate", default=0.0, show_default=True, type=FiniteFloat(0, 1))
@click.option("--corrupt", default=0.0, show_default=True, type=FiniteFloat(0, 1), help="Flip one bit.")
@click.option("--reorder", default=0.0, show_default=True, type=FiniteFloat(0, 1),
              help="Hold a packet back 30 ms.")
@click.option("--delay-ms", default=0.0, show_default=True, type=FiniteFloat(0, 10000))
@click.option("--jitter-ms", default=0.0, show_default=True, type=FiniteFloat(0, 10000))
@click.option("--seed", default=0, show_default=True, type=int)
@click.option("--seconds", default=None, type=FiniteFloat(min=0.1), help="Stop after this long.")
def relay(listen: str, target: str, loss: float, burst_ms: float, duplicate: float, corrupt: float, reorder: float,
          delay_ms: float, jitter_ms: float, seed: int, seconds: float | None) -> None:
    """A bad network on one machine: forward UDP from --listen to --to (and replies back),
    losing, delaying, reordering, duplicating and corrupting packets at random (seeded).

    Example: `toonface relay --to 127.0.0.1:7710 --loss 0.1 --burst-ms 50`, then
    `toonface send synthetic --to 127.0.0.1:7711`.
    """
    from stream.relay import NetworkFaults, Relay

    faults = NetworkFaults(loss=loss, burst_seconds=burst_ms / 1000, duplicate=duplicate, corrupt=corrupt,
                           reorder=reorder, delay=delay_ms / 1000, jitter=jitter_ms / 1000)
    try:
        proxy = Relay(_required_address(listen, "--listen", 7711), _required_address(target, "--to", 7710), faults,
                      seed)
    except OSError as exc:
        raise click.BadParameter(f"cannot listen on {listen}: {exc.strerror or exc}", param_hint="--listen") from None
    with proxy:
        host, port = proxy.address
        click.echo(f"relaying {host}:{port} -> {target} (Ctrl-C stops)", err=False)
        start = time.monotonic()
        end = None if seconds is None else start + seconds
        try:
            while end is None or time.monotonic() < end:
                time.sleep(0.2 if end is None else max(0.0, min(0.2, end - time.monotonic())))
        except KeyboardInterrupt:
            pass
        elapsed = max(time.monotonic() - start, 1e-9)
    counts = {side: {**plan.counts, "wire_kbps": round(plan.flowing_kbps(), 3)}  # while it flowed, not idle too
              for side, plan in (("forward", proxy.forward), ("back", proxy.backward))}
    both = round(sum(c["wire_kbps"] for c in counts.values()), 3)
    click.echo(json.dumps({**counts, "wire_kbps_both": both, "seconds": round(elapsed, 2)}))


STREAM_COMMANDS = (send, receive, relay)
