"""The documentation site (issue 47): it builds with --strict (no broken link, no missing page), its
command reference is generated from the click commands, and the getting-started page's commands
run as written on the shared take they name."""

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
REALDATA = ROOT.parent / "shared" / "realdata"

pytestmark = pytest.mark.slow


def test_the_site_builds_strictly_with_every_command_in_its_reference(tmp_path):
    pytest.importorskip("mkdocs", reason="the docs extra is not installed (make installs it)")
    pytest.importorskip("mkdocs_click", reason="the docs extra is not installed (make installs it)")
    built = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-q", "-d", str(tmp_path / "site")],
                           cwd=ROOT, capture_output=True, text=True, env={**os.environ, "NO_MKDOCS_2_WARNING": "1"})
    assert built.returncode == 0, built.stderr[-2000:]
    reference = (tmp_path / "site" / "reference" / "commands" / "index.html").read_text()
    from toonface.cli import cli

    for name in cli.commands:  # every command, from the code
        assert f'id="toonface-{name}"' in reference, name
    assert "Sentinel" not in reference  # (click's unset defaults are not shown as such)
    changelog = (tmp_path / "site" / "changelog" / "index.html").read_text()
    assert "issue 45" in changelog  # CHANGELOG.md is the page


def test_the_getting_started_commands_run_as_written(tmp_path, monkeypatch):
    import av

    from toonface.cli import main

    take = REALDATA / "facial" / "animface" / "JawMoCap.csv"
    if not take.is_file():
        pytest.skip(f"the shared take is absent ({take})")
    page = (ROOT / "docs" / "getting-started.md").read_text()
    blocks = re.findall(r"```sh\n(.*?)```", page.split("## A first cartoon", 1)[1], re.S)
    commands = [line.strip() for block in blocks for line in block.splitlines() if line.strip()]
    assert commands and all(c.startswith("toonface ") for c in commands)
    shutil.copy(take, tmp_path)
    monkeypatch.chdir(tmp_path)
    for command in commands:
        assert main(shlex.split(command)[1:]) == 0, command
    with av.open(str(tmp_path / "jaw-cat.mp4")) as made:
        assert made.streams.video[0].frames > 100
