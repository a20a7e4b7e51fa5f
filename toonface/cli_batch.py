"""The ``batch`` subcommand: a job file's takes x faces on a local or remote Dask cluster."""

from __future__ import annotations

import logging
import sys

import click


@click.command()
@click.argument("job_file", metavar="JOBS.toml", type=click.Path(dir_okay=False))
@click.option("--scheduler", default=None, metavar="ADDRESS",
              help="A running Dask scheduler, such as tcp://10.0.0.5:8786 [default: a local cluster here].")
@click.option("--workers", default=None, type=click.IntRange(1, 4096),
              help="Local cluster: worker processes, one thread each [default: one per core]. "
                   "With --scheduler: wait (up to a minute) until this many workers have joined.")
@click.option("--force", is_flag=True, help="Make every output again, even those up to date.")
@click.option("--dry-run", is_flag=True, help="List each pair and what it would make; run nothing.")
@click.option("--manifest", default=None, type=click.Path(dir_okay=False),
              help="Where to write the JSON manifest [default: OUTPUT/manifest.json].")
@click.pass_context
def batch(ctx: click.Context, job_file: str, scheduler: str | None, workers: int | None, force: bool,
          dry_run: bool, manifest: str | None) -> None:
    """Retarget every take of a job file onto every face of it, in parallel, on Dask.

    For each (take, face) pair it writes, under the job's output folder, TAKE/FACE.mp4, the
    motor track TAKE/FACE.csv, a score plot TAKE/FACE.score.png and a contact sheet
    TAKE/FACE.sheet.png (the job file: docs/tutorials/batch.md). Long videos are rendered in parts
    on several workers and joined. Outputs appear only when complete; a pair whose take, face,
    mapping, profile and settings are unchanged since its outputs were made is skipped, so an
    interrupted job picks up where it stopped. A take or face that cannot be used fails only its
    own pairs.

    Prints a table (pairs done, skipped, failed, frames, time) and writes a JSON manifest of
    every output with its input hashes. Exit status: 0 when every pair is done or skipped, 1
    when any failed, 2 for a bad job file.
    """
    # Imported here: Dask takes half a second to import, which every other subcommand would pay.
    from toonface.batch import connect, load_job, plan, run_batch, write_manifest

    if logging.getLogger().getEffectiveLevel() > logging.INFO:  # Dask logs every start and stop at INFO
        logging.getLogger("distributed").setLevel(logging.WARNING)
    job = load_job(job_file)
    for pattern in job.empty_globs:
        click.echo(f"warning: {job.path}: takes: {pattern!r} matches no take file", err=True)
    if job.passed_over:
        names = ", ".join(p.name for p in job.passed_over[:5]) + (", ..." if len(job.passed_over) > 5 else "")
        click.echo(f"warning: {job.path}: takes: {len(job.passed_over)} videos or voices left out ({names}): a batch "
                   "reads marker takes; `toonface retarget` each one", err=True)
    pairs = plan(job, force)
    if dry_run:
        for pair in pairs:
            what = f"FAILS: {pair.error}" if pair.error else (
                f"makes {', '.join(pair.stale)}" if pair.stale else "up to date, skipped")
            click.echo(f"{pair.name}: {what}")
        return
    todo = sum(1 for p in pairs if p.stale and not p.error)
    click.echo(f"{len(pairs)} pairs ({len(job.takes)} takes x {len(job.faces)} faces): {todo} to make, "
               f"{sum(1 for p in pairs if not p.stale)} up to date")
    if todo:
        with connect(scheduler, workers) as client, _TaskBar() as bar:
            report = run_batch(job, pairs, client, bar.update)
    else:
        report = run_batch(job, pairs, None)
    path = write_manifest(report, manifest or job.output / "manifest.json")
    for line in report.table():
        click.echo(line)
    for line in report.warned():
        click.echo(f"warning: {line}", err=True)
    for line in report.failures():
        click.echo(f"failed: {line}", err=True)
    click.echo(f"wrote {path}")
    if not report.ok:
        ctx.exit(1)


class _TaskBar:
    """A progress bar over tasks on stderr (only on a terminal); the total grows as tasks are submitted."""

    def __enter__(self) -> _TaskBar:
        from tqdm import tqdm

        self.bar = tqdm(total=0, desc="batch", unit="task", file=sys.stderr, disable=None, leave=False)
        return self

    def update(self, finished: int, submitted: int) -> None:
        self.bar.total = submitted
        self.bar.update(finished - self.bar.n)

    def __exit__(self, *exc) -> None:
        self.bar.close()


BATCH_COMMANDS = (batch,)
