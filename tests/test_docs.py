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
    reference = (tmp_path / "site" / "reference" / "commands.html").read_text()
    from toonface.cli import cli

    for name in cli.commands:  # every command, from the code
        assert f'id="toonface-{name}"' in reference, name
    assert "Sentinel" not in reference  # (click's unset defaults are not shown as such)
    changelog = (tmp_path / "site" / "changelog.html").read_text()
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


def test_the_api_page_is_the_code_s_and_its_example_runs(tmp_path, monkeypatch):
    """The Python API page: its example runs as written on the shared take, and the page built
    from the docstrings names every public function of every stage, with no Sphinx role left raw."""
    pytest.importorskip("mkdocstrings", reason="the docs extra is not installed (make installs it)")
    take = REALDATA / "facial" / "animface" / "JawMoCap.csv"
    if not take.is_file():
        pytest.skip(f"the shared take is absent ({take})")
    example = re.findall(r"```python\n(.*?)```", (ROOT / "docs" / "reference" / "api.md").read_text(), re.S)[0]
    shutil.copy(take, tmp_path)
    monkeypatch.chdir(tmp_path)
    exec(compile(example, "api.md", "exec"), {})
    import av

    with av.open(str(tmp_path / "jaw-cat.mp4")) as made:
        assert made.streams.video[0].frames == 1590
    built = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-q", "-d", str(tmp_path / "site")],
                           cwd=ROOT, capture_output=True, text=True, env={**os.environ, "NO_MKDOCS_2_WARNING": "1"})
    assert built.returncode == 0, built.stderr[-2000:]
    page = (tmp_path / "site" / "reference" / "api.html").read_text()
    import importlib

    for package in ("toonface", "capture", "mapping", "toon", "player", "stream", "common"):
        for name in importlib.import_module(package).__all__:
            ids = (f'id="{package}.{name}"', f'id="{package}.{name}.{name}"')  # (a function named as its module)
            assert any(i in page for i in ids), f"{package}.{name}"
    assert not re.search(r":(func|class|meth|mod|data|attr):<code>", page)


def test_the_readme_is_short_and_its_links_lead_somewhere():
    readme = (ROOT / "README.md").read_text()
    assert len(readme.splitlines()) < 80 and readme.startswith("# toonface\n\n```sh\nmake demo")
    links = re.findall(r"\]\(([^)#]+)\)", readme)
    assert len(links) > 20
    for link in links:
        assert (ROOT / link).is_file(), link


def test_every_picture_is_made_by_the_pictures_script_and_shown_on_a_page():
    """`make pictures` makes every picture in docs/images, and each one is on some page."""
    script = (ROOT / "scripts" / "docs-pictures.py").read_text()
    pages = "".join(p.read_text() for p in [ROOT / "README.md", *(ROOT / "docs").rglob("*.md")])
    for picture in (ROOT / "docs" / "images").iterdir():
        face = re.fullmatch(r"face-(\w+)\.png", picture.name)
        assert picture.name in script or (face and "face-NAME.png" in script), picture.name
        assert f"images/{picture.name}" in pages, picture.name


def test_a_first_time_reader_gets_from_the_home_page_to_a_cartoon_by_links_only(tmp_path, capsys):
    """The built site in Chromium: from the home page, the link a newcomer is pointed to, then the
    commands as the page shows them, run on the shared take. Prints how long each part took (the
    reading is estimated at 200 words a minute)."""
    import time

    pytest.importorskip("mkdocs", reason="the docs extra is not installed (make installs it)")
    sys.path.insert(0, str(ROOT / "tests" / "helpers"))
    from browser import chromium

    from toonface.cli import main

    take = REALDATA / "facial" / "animface" / "JawMoCap.csv"
    if not take.is_file():
        pytest.skip(f"the shared take is absent ({take})")
    built = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-q", "-d", str(tmp_path / "site")],
                           cwd=ROOT, capture_output=True, text=True, env={**os.environ, "NO_MKDOCS_2_WARNING": "1"})
    assert built.returncode == 0, built.stderr[-2000:]
    with chromium(1280, 900) as driver:
        driver.get((tmp_path / "site" / "index.html").as_uri())
        words = len(driver.find_element("tag name", "article").text.split())
        driver.find_element("link text", "Getting started").click()  # the home page's "New here?" link
        assert driver.current_url.endswith("/getting-started.html")
        article = driver.find_element("tag name", "article")
        words += len(article.text.split())
        first = article.text.split("A first cartoon of a real take", 1)[1]
        shown = [block.text for block in article.find_elements("css selector", "pre code")]
    commands = [line for block in shown for line in block.splitlines() if line.startswith("toonface ")]
    assert commands and all(c in first for c in commands)  # what the page shows, under its heading
    folder = tmp_path / "mine"
    folder.mkdir()
    shutil.copy(take, folder)  # as the page says: the shared take copied into a folder of one's own
    started = time.perf_counter()
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        for command in commands:
            assert main(shlex.split(command)[1:]) == 0, command
    finally:
        os.chdir(cwd)
    ran = time.perf_counter() - started
    import av

    with av.open(str(folder / "jaw-cat.mp4")) as made:
        assert made.streams.video[0].frames == 1590
    with capsys.disabled():
        print(f"\nfirst-time reader: {words} words read (about {words / 200:.1f} min at 200 a minute), "
              f"{len(commands)} commands run in {ran:.1f} s")
