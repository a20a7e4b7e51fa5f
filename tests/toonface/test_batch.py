"""Batch jobs: job files, plans and stamps, parts joined into one video, and whole jobs on a local
Dask cluster of two worker processes (several takes x faces, a corrupt take, a worker killed
mid-job, a rerun that skips everything)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import av
import numpy as np
import pytest
from batch_jobs import SIZE, run, write_job
from distributed import get_task_stream

from capture import load_take, save_take, synthesize
from common import InputError
from player.parts import frame_ranges, join_parts, render_part
from toon import FaceRig, load_face, load_track, save_face
from toonface.batch import connect, load_job, plan, run_batch, tasks
from toonface.batch import pairs as batch_pairs
from toonface.batch.pairs import file_digest as digest
from toonface.cli import main
from toonface.pipeline import map_onto_face, render


def decode(path: Path) -> list[np.ndarray]:
    with av.open(str(path)) as container:
        return [f.to_ndarray(format="rgb24") for f in container.decode(video=0)]


def mean_errors(frames: list[np.ndarray], reference: list[np.ndarray]) -> np.ndarray:
    return np.array([np.abs(a.astype(int) - b).mean() for a, b in zip(frames, reference, strict=True)])


# --- job files ---------------------------------------------------------------------------------

@pytest.mark.parametrize("extra, field", [
    ('colour = "red"\n', "colour"),
    ('[render]\nsize = "65"\n', "render.size"),
    ('[write]\nmotors = "xml"\n', "write.motors"),
    ('[write]\nvideo = false\nmotors = false\nscore = false\nsheet = false\n', "write"),
    ('neutral = [2, 1]\n', "neutral"),
    ('[clean]\ncutoff = -1\n', "clean.cutoff"),
    ('[write]\nvideo = "gif"\n', "write.video"),
    ('[render]\nbackground = "pink"\n', "render.background"),
    ('[render]\nbackground = "none"\n', "render.background"),  # an MP4 has no alpha
])
def test_a_bad_job_file_names_the_field(tmp_path, extra, field):
    path = tmp_path / "job.toml"
    lines = ['format = "toonface.batch/1"', 'takes = ["*.npz"]', 'faces = ["classic"]']
    path.write_text("\n".join(lines) + "\n" + extra)
    save_take(synthesize(seconds=1.0, rate=30.0).take, tmp_path / "a.npz")
    with pytest.raises(InputError) as err:
        load_job(path)
    assert err.value.field == field and err.value.source == str(path)


def test_a_job_without_takes_is_an_error_and_an_empty_glob_is_reported(tmp_path):
    path = write_job(tmp_path, {"a": 1.0}, ["classic"])
    job = load_job(path)
    assert [t.name for t in job.takes] == ["a.npz"] and job.empty_globs == ("takes/*.c3d",)
    (tmp_path / "takes" / "a.npz").unlink()
    with pytest.raises(InputError, match="no take file"):
        load_job(path)


def test_videos_and_voices_a_glob_matches_are_said_to_be_left_out(tmp_path, capsys):
    """A batch reads marker takes; a glob over a folder that also holds videos and voices, which
    map and retarget read, left them out without a word (and with nothing else, said no take matched)."""
    from toonface.cli import main

    path = write_job(tmp_path, {"a": 1.0}, ["classic"])
    path.write_text(path.read_text().replace('takes = ["takes/*.npz", "takes/*.c3d"]', 'takes = ["takes/*"]'))
    for name in ("talk.mp4", "line.wav", "notes.md"):
        (tmp_path / "takes" / name).write_bytes(b"")
    job = load_job(path)
    assert [t.name for t in job.takes] == ["a.npz"] and [p.name for p in job.passed_over] == ["line.wav", "talk.mp4"]
    assert main(["batch", str(path), "--dry-run"]) == 0
    assert ("takes: 2 videos or voices left out (line.wav, talk.mp4): a batch reads marker takes; `toonface "
            "retarget` each one") in capsys.readouterr().err
    (tmp_path / "takes" / "a.npz").unlink()
    with pytest.raises(InputError, match="it matches 2 videos or voices, which a batch does not read"):
        load_job(path)


def test_outputs_are_never_taken_for_takes(tmp_path):
    path = write_job(tmp_path, {"a": 1.0}, ["classic"])
    path.write_text(path.read_text().replace('takes = ["takes/*.npz", "takes/*.c3d"]', 'takes = ["**/*.npz"]'))
    (tmp_path / "out" / "a").mkdir(parents=True)
    save_take(synthesize(seconds=1.0, rate=30.0).take, tmp_path / "out" / "a" / "classic.npz")
    assert [t.relative_to(tmp_path).as_posix() for t in load_job(path).takes] == ["takes/a.npz"]


def test_plan_names_outputs_and_keys_follow_their_inputs(tmp_path):
    path = write_job(tmp_path, {"a": 1.0, "b": 1.0}, ["classic", "faces/mine.json"])
    (tmp_path / "faces").mkdir()
    save_face(load_face("round"), tmp_path / "faces" / "mine.json")
    pairs = plan(load_job(path))
    assert [p.name for p in pairs] == ["a/classic", "a/mine", "b/classic", "b/mine"]
    assert pairs[1].output("video").path == tmp_path / "out" / "a" / "mine.mp4"
    assert pairs[0].output("motors").path.name == "classic.csv"
    assert all(p.stale == ("motors", "video", "score", "sheet") for p in pairs)
    # the same take and settings on another face: the same take hash, a different face hash and keys
    assert pairs[0].inputs["take"] == pairs[1].inputs["take"] != pairs[2].inputs["take"]
    assert pairs[0].output("video").key != pairs[1].output("video").key
    # a bigger frame changes the video's and nothing else's key
    path.write_text(path.read_text().replace(f'size = "{SIZE}"', 'size = "128"'))
    again = plan(load_job(path))
    assert again[0].output("video").key != pairs[0].output("video").key
    assert again[0].output("motors").key == pairs[0].output("motors").key


def test_a_missing_face_fails_its_pairs_at_planning(tmp_path):
    path = write_job(tmp_path, {"a": 1.0}, ["classic", "faces/none.json"])
    pairs = plan(load_job(path))
    assert pairs[0].error == "" and "no such face file" in pairs[1].error


# --- parts ---------------------------------------------------------------------------------------

def test_frame_ranges_cover_every_frame_once():
    for frames in (1, 7, 100, 101):
        for most in (1, 3, 50, 200):
            ranges = frame_ranges(frames, most)
            assert ranges[0][0] == 0 and ranges[-1][1] == frames
            ends = ranges[1:] + [(frames, 0)]
            assert all(a < b <= a + most and b == c for (a, b), (c, _) in zip(ranges, ends, strict=True))


@pytest.mark.gl
@pytest.mark.parametrize("fps", [30.0, 24.0, 60.0])
def test_a_part_resamples_only_its_own_frames_and_they_are_the_whole_videos(fps):
    from player.offline import resample
    from toon import MotorTrack

    track = MotorTrack(np.random.default_rng(0).random((100, 21)), 30.0)
    whole = resample(track, fps)
    for start, stop in ((0, 10), (5, 37), (40, None)):
        np.testing.assert_array_equal(resample(track, fps, start, stop), whole[start:stop])
    assert resample(track, 60.0, 10, 12) == pytest.approx(
        np.array([[np.interp(t, track.times, c) for c in track.values.T] for t in (10 / 60, 11 / 60)]))


@pytest.mark.slow  # over a second: make test runs it, test-fast does not
def test_parts_join_into_the_whole_video_in_order(tmp_path):
    track = map_onto_face(synthesize(seconds=2.0, rate=30.0, seed=3).take)
    rig = FaceRig(load_face("classic"))
    parts = [render_part(track, rig, a, b, 30.0, (SIZE, SIZE), samples=0) for a, b in frame_ranges(60, 16)]
    assert len(parts) == 4
    assert join_parts(parts, tmp_path / "joined.mp4") == 60
    assert render(track, rig.face, tmp_path / "whole.mp4", (SIZE, SIZE), samples=0) == 60
    whole = decode(tmp_path / "whole.mp4")
    errors = mean_errors(decode(tmp_path / "joined.mp4"), whole)
    assert errors.max() < 2.5  # two H.264 encodings (crf 18) of the same 64-pixel frames
    # the comparison can fail: the parts in the wrong order are far off where the face moves
    assert join_parts(parts[2:] + parts[:2], tmp_path / "swapped.mp4") == 60
    assert mean_errors(decode(tmp_path / "swapped.mp4"), whole).max() > 2 * errors.max()
    with av.open(str(tmp_path / "joined.mp4")) as container:
        stream = container.streams.video[0]
        assert stream.average_rate == 30 and float(stream.duration * stream.time_base) == pytest.approx(2.0)
        times = [f.time for f in container.decode(video=0)]
    assert np.allclose(np.diff(times), 1 / 30)


# --- whole jobs on a local cluster -------------------------------------------------------------

@pytest.fixture(scope="module")
def client():
    """A local cluster of two worker processes, one thread each, shared by this module's jobs."""
    with connect(None, workers=2) as dask_client:
        yield dask_client


@pytest.mark.slow
def test_a_job_makes_every_output_and_a_rerun_skips_them_all(tmp_path, client, monkeypatch):
    path = write_job(tmp_path, {"a": 2.0, "b": 1.0, "c": 1.3}, ["classic", "round"])
    with get_task_stream(client) as stream:
        report = run(path, client)
    assert report.ok and report.count("done") == 6
    ran = [record["key"].split("-")[0] for record in stream.data]
    assert ran.count("ready") == 3 and ran.count("map") == 6  # each take cleaned once for its two faces
    out = tmp_path / "out"
    for take, seconds in (("a", 2.0), ("b", 1.0), ("c", 1.3)):
        for face in ("classic", "round"):
            assert {p.name for p in (out / take).glob(f"{face}.*")} == {
                f"{face}.csv", f"{face}.mp4", f"{face}.score.png", f"{face}.sheet.png"}
            # the motors the cluster wrote are the ones the one-machine pipeline maps
            mapped = map_onto_face(load_take(tmp_path / "takes" / f"{take}.npz"), face=load_face(face))
            assert np.allclose(load_track(out / take / f"{face}.csv").values, mapped.values, atol=1e-6)
            assert len(decode(out / take / f"{face}.mp4")) == mapped.frames == round(seconds * 30)
    assert report.results[0].frames == 60 and report.results[0].seconds > 0
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["totals"] == {"done": 6, "skipped": 0, "failed": 0, "cancelled": 0}
    entry = manifest["pairs"][0]
    assert entry["name"] == "a/classic" and all(o["written"] and o["up_to_date"] for o in entry["outputs"])
    assert entry["outputs"][1]["bytes"] == (out / "a" / "classic.mp4").stat().st_size

    before = {p: p.stat().st_mtime_ns for p in out.rglob("*") if p.is_file() and p.name != "manifest.json"}
    calls = []
    again = run(path, client, progress=lambda *a: calls.append(a))
    assert again.count("skipped") == 6 and calls == []  # nothing submitted
    assert {p: p.stat().st_mtime_ns for p in before} == before
    assert [r.frames for r in again.results] == [r.frames for r in report.results]
    # the same bytes with a new time are hashed again and found unchanged; unchanged files are not read
    os.utime(tmp_path / "takes" / "a.npz")
    read = []
    monkeypatch.setattr(batch_pairs, "file_digest", lambda p: read.append(Path(p).name) or digest(p))
    assert run(path, client).count("skipped") == 6
    assert [name for name in read if name.endswith(".npz")] == ["a.npz"]
    monkeypatch.undo()

    # a changed take remakes its own pairs only; a changed setting only the outputs it shapes
    save_take(synthesize(seconds=1.0, rate=30.0, seed=9).take, tmp_path / "takes" / "b.npz")
    changed = run(path, client)
    assert [r.pair.name for r in changed.results if r.status == "done"] == ["b/classic", "b/round"]
    path.write_text(path.read_text().replace(f'size = "{SIZE}"', 'size = "48"'))
    resized = run(path, client)
    assert resized.count("done") == 6 and all(set(r.written) == {"video"} for r in resized.results)
    assert decode(out / "a" / "round.mp4")[0].shape == (48, 48, 3)


@pytest.mark.slow
def test_a_corrupt_take_fails_only_its_own_pairs(tmp_path, client):
    path = write_job(tmp_path, {"a": 1.0, "b": 1.0}, ["classic", "round"])
    (tmp_path / "takes" / "broken.c3d").write_bytes(b"\x02\x50" + bytes(100))
    report = run(path, client)
    failed = {r.pair.name: r.reason for r in report.results if r.status == "failed"}
    assert set(failed) == {"broken/classic", "broken/round"}
    assert all(str(tmp_path / "takes" / "broken.c3d") in reason for reason in failed.values())
    assert report.count("done") == 4 and not report.ok
    assert not (tmp_path / "out" / "broken").exists()
    assert not list((tmp_path / "out").rglob("*.partial*"))  # no half-written output anywhere


@pytest.mark.slow
def test_a_worker_killed_mid_job_has_its_tasks_run_elsewhere(tmp_path, client):
    client.wait_for_workers(2, timeout=60)
    path = write_job(tmp_path, {"a": 2.0, "b": 2.0, "c": 2.0}, ["classic", "round"])
    pids = client.run(os.getpid)
    killed = []

    def kill_a_busy_worker(finished: int, submitted: int) -> None:
        if killed:
            return
        busy = [address for address, keys in client.processing().items() if keys]
        if busy:
            killed.append((busy[0], tuple(client.processing()[busy[0]])))
            os.kill(pids[busy[0]], signal.SIGKILL)

    report = run(path, client, progress=kill_a_busy_worker)
    assert killed and killed[0][1], "no worker was busy when the first task finished"
    assert report.ok and report.count("done") == 6, [(r.pair.name, r.status, r.reason) for r in report.results]
    for pair in report.results:
        assert len(decode(pair.pair.output("video").path)) == 60
    client.wait_for_workers(2, timeout=60)  # its nanny starts a new one


@pytest.mark.slow
def test_the_command_reports_failures_in_its_exit_status(tmp_path, capsys):
    path = write_job(tmp_path, {"a": 1.0}, ["classic"], "[write]\nsheet = false\nscore = false\n")
    (tmp_path / "takes" / "broken.c3d").write_bytes(b"not a c3d")
    assert main(["batch", str(path), "--dry-run"]) == 0
    assert capsys.readouterr().out.splitlines() == ["a/classic: makes motors, video",
                                                    "broken/classic: makes motors, video"]
    assert main(["batch", str(path), "--workers", "2"]) == 1
    captured = capsys.readouterr()
    assert "done            1" in captured.out and "failed          1" in captured.out
    assert captured.err.startswith("failed: broken/classic: ") and "not a C3D file" in captured.err
    (tmp_path / "takes" / "broken.c3d").unlink()
    # everything up to date: no cluster is started. In a fresh process, where no Dask client
    # exists (this one has the module's), as a user's rerun runs: it used to end in "No clients found".
    rerun = subprocess.run([sys.executable, "-m", "toonface", "batch", str(path)], capture_output=True, text=True,
                           timeout=120)
    assert rerun.returncode == 0, rerun.stderr
    assert "skipped         1" in rerun.stdout


@pytest.mark.slow
def test_the_command_runs_on_an_existing_scheduler(tmp_path, client, capsys):
    path = write_job(tmp_path, {"a": 1.0}, ["classic", "round"], "[write]\nsheet = false\n")
    address = client.scheduler.address
    assert main(["batch", str(path), "--scheduler", address, "--workers", "2"]) == 0
    assert "done            2" in capsys.readouterr().out
    manifest = json.loads((tmp_path / "out" / "manifest.json").read_text())
    assert manifest["scheduler"] == address and manifest["workers"] == 2
    assert main(["batch", str(path), "--scheduler", "tcp://127.0.0.1:9", "--force"]) == 2
    assert "cannot reach the Dask scheduler" in capsys.readouterr().err


def test_a_bad_job_file_is_one_line_and_status_2(tmp_path, capsys):
    path = tmp_path / "job.toml"
    path.write_text('format = "toonface.batch/1"\ntakes = ["*.npz"]\nfaces = ["classic"]\n')
    assert main(["batch", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"toonface: error: {path}: takes: no take file")


def test_csv_options_apply_to_csv_takes_only(tmp_path):
    """A job with [csv] units = "cm" failed every .c3d and .npz pair ('a .npz take carries its own units')."""
    path = write_job(tmp_path, {"a": 1.0}, ["classic"], '[csv]\nunits = "cm"\n')
    take = synthesize(seconds=1.0, rate=30.0, seed=0).take
    in_cm = replace(take, positions=take.positions / 10.0, meta={})
    save_take(in_cm, tmp_path / "takes" / "b.csv")
    job = load_job(path)
    from_npz = tasks.map_pair(tasks.ready_pair_take(tmp_path / "takes" / "a.npz", job), "classic")
    from_csv = tasks.map_pair(tasks.ready_pair_take(tmp_path / "takes" / "b.csv", job), "classic")  # cm: the same
    assert np.allclose(from_npz.values, from_csv.values, atol=1e-4)


def test_takes_from_other_folders_get_flat_output_folders(tmp_path):
    """A take given by a path outside the job's folder landed in out/<every folder of its path>/."""
    elsewhere = tmp_path / "far" / "away" / "session"
    for day in ("day1", "day2"):
        (elsewhere / day).mkdir(parents=True)
        save_take(synthesize(seconds=1.0, rate=30.0).take, elsewhere / day / "take.npz")
    save_take(synthesize(seconds=1.0, rate=30.0).take, elsewhere / "JawMoCap.npz")
    job_dir = tmp_path / "jobs"
    job_dir.mkdir()
    path = job_dir / "job.toml"
    path.write_text(f'format = "toonface.batch/1"\ntakes = ["{elsewhere}/**/*.npz"]\nfaces = ["classic"]\n'
                    'output = "out"\n')
    outputs = {p.name: p.output("video").path for p in plan(load_job(path))}
    assert outputs == {"JawMoCap/classic": job_dir / "out" / "JawMoCap" / "classic.mp4",
                       "day1-take/classic": job_dir / "out" / "day1-take" / "classic.mp4",
                       "day2-take/classic": job_dir / "out" / "day2-take" / "classic.mp4"}


def test_dry_run_lists_what_a_changed_setting_remakes_as_the_readme_says(tmp_path, capsys):
    """The batch page said a changed size remakes videos and sheets; --dry-run listed only the videos."""
    path = write_job(tmp_path, {"a": 1.0}, ["classic"])
    pair = plan(load_job(path))[0]
    for kind in pair.stale:  # pretend a run made them all
        pair.output(kind).path.parent.mkdir(parents=True, exist_ok=True)
        pair.output(kind).path.write_bytes(b"x")
    batch_pairs.write_stamp(pair, {kind: 1 for kind in pair.stale}, 30)
    assert plan(load_job(path))[0].stale == ()
    page = (Path(__file__).resolve().parents[2] / "docs" / "tutorials" / "batch.md").read_text()
    assert "changing `size` or `fps` remakes the videos only, `samples` the videos and contact sheets" in page
    for old, new, remade in ((f'size = "{SIZE}"', 'size = "48"', "makes video"),
                             ("samples = 0", "samples = 2", "makes video, sheet")):
        path.write_text(path.read_text().replace(old, new))
        assert main(["batch", str(path), "--dry-run"]) == 0
        assert capsys.readouterr().out.strip() == f"a/classic: {remade}"
        path.write_text(path.read_text().replace(new, old))


@pytest.mark.slow
def test_each_pair_keeps_its_takes_report_and_the_summary_names_takes_with_warnings(tmp_path, capsys):
    """The per-take report of map, kept per pair in the manifest and the stamp: a rerun that
    skips the pair still lists the take whose report holds a warning."""
    path = write_job(tmp_path, {"fine": 1.0}, ["classic"], "[write]\nsheet = false\nscore = false\nvideo = false\n")
    syn = synthesize(seconds=1.0, rate=30.0, seed=5).take
    save_take(type(syn)(syn.positions / 10.0, syn.labels, syn.rate), tmp_path / "takes" / "cm.npz")
    for _ in range(2):  # made, then skipped
        assert main(["batch", str(path), "--workers", "1"]) == 0
        captured = capsys.readouterr()
        warned = [line for line in captured.err.splitlines()
                  if line.startswith("warning: ") and "matches no" not in line]  # the job's unused c3d glob
        assert len(warned) == 1 and warned[0].startswith("warning: cm/classic: units: cm.npz read in"), captured.err
        manifest = json.loads((tmp_path / "out" / "manifest.json").read_text())
        reports = {p["name"]: p["report"] for p in manifest["pairs"]}
        assert reports["cm/classic"]["warnings"][0].startswith("units: cm.npz read in the units its file states")
        assert reports["fine/classic"]["warnings"] == [] and reports["fine/classic"]["units"]["unit"] == "mm"
        assert reports["fine/classic"]["motors"]["MB"]["range_used"] >= 0
    assert "skipped         2" in captured.out


@pytest.mark.slow
def test_ctrl_c_cancels_the_pairs_in_flight_without_dask_tracebacks(tmp_path, client, monkeypatch):
    """Ctrl-C while the first tasks ran printed 35 lines of the scheduler's own tracebacks
    ("Exception while handling op register-client") before "aborted": Dask's loggers are quiet
    once the user has stopped the run."""
    import logging

    for name in [n for n in logging.root.manager.loggerDict if n.split(".")[0] in ("distributed", "asyncio")]:
        monkeypatch.setattr(logging.getLogger(name), "level", logging.getLogger(name).level)  # restored after
    path = write_job(tmp_path, {"a": 2.0, "b": 2.0}, ["classic", "round"])
    job = load_job(path)

    def stop(finished: int, submitted: int) -> None:
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_batch(job, plan(job), client, stop)
    for name in ("distributed", "distributed.core", "distributed.scheduler", "asyncio"):
        assert not logging.getLogger(name).isEnabledFor(logging.CRITICAL), name
