"""Batch jobs writing the picture formats other tools take (issue 41): WebM with alpha, an
animated SVG, the web player, APNG, on a local Dask cluster."""

from __future__ import annotations

import re

import pytest
from batch_jobs import run, write_job

from toonface.batch import connect


@pytest.fixture(scope="module")
def client():
    """A local cluster of one worker process."""
    with connect(None, workers=1) as dask_client:
        yield dask_client


@pytest.mark.slow
def test_a_job_writes_each_picture_format_it_names(tmp_path, client):
    from player.alpha_sinks import decode_rgba

    path = write_job(tmp_path, {"a": 1.0}, ["cat"], '[write]\nscore = false\nsheet = false\nvideo = "webm"\n')
    path.write_text(path.read_text().replace("part_seconds = 0.5", 'part_seconds = 0.5\nbackground = "none"'))
    for video in ("webm", "svg", "html", "apng"):
        path.write_text(re.sub(r'video = "\w+"', f'video = "{video}"', path.read_text()))
        report = run(path, client)
        assert report.ok, video
        written = tmp_path / "out" / "a" / f"cat.{video}"
        assert written.is_file() and written.stat().st_size > 1000, video
    frames = decode_rgba(tmp_path / "out" / "a" / "cat.webm")
    assert len(frames) == 30 and frames[0][0, 0, 3] == 0  # transparent, as the job said
    assert "<animate" in (tmp_path / "out" / "a" / "cat.svg").read_text()
    assert "window.player" in (tmp_path / "out" / "a" / "cat.html").read_text()
