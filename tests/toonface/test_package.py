"""A regular (non-editable) install works away from the checkout: every built-in file is in the wheel."""

import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _tracked_files() -> list[str]:
    out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
    return [name for name in out.decode().split("\0") if name]


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """The wheel built from a copy of the tracked files (nothing left over from the checkout's builds)."""
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("needs a git checkout to know the tracked files")
    src = tmp_path_factory.mktemp("src")
    for name in _tracked_files():
        if (ROOT / name).is_file():
            (src / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / name, src / name)
    dist = tmp_path_factory.mktemp("dist")
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "--no-build-isolation",
                    "--disable-pip-version-check", "-w", str(dist), str(src)], check=True, capture_output=True)
    (found,) = dist.glob("toonface-*.whl")
    return found


@pytest.mark.slow  # a few seconds; make test runs it (make test-fast stays under a minute)
def test_the_wheel_carries_every_built_in_file(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    for path in sorted((ROOT / "data").rglob("*")):
        if path.is_file() and path.suffix in {".toml", ".json", ".py"}:
            assert f"toonface_data/{path.relative_to(ROOT / 'data').as_posix()}" in names
    assert "toon/__init__.pyi" in names


@pytest.mark.slow
def test_an_installed_wheel_runs_demo_and_map_from_an_empty_folder(wheel, tmp_path):
    env_dir = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(env_dir)], check=True)
    python = env_dir / "bin" / "python"
    site = Path(subprocess.run([python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                               capture_output=True, text=True, check=True).stdout.strip())
    subprocess.run([sys.executable, "-m", "pip", "--python", str(python), "install", "--quiet", "--no-deps",
                    "--disable-pip-version-check", str(wheel)], check=True, capture_output=True)
    # Only after the install (pip would replace the toonface it found there): the dependencies come
    # from this environment's site-packages as a plain path. Its .pth files (the checkout's editable
    # finder among them) are not run, so only the wheel provides toonface.
    (site / "deps.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    work = tmp_path / "empty"
    work.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in {"PYTHONPATH", "TOONFACE_DATA"}}
    where = subprocess.run([python, "-c", "import toonface, toonface_data; print(toonface.__file__); "
                            "print(toonface_data.__file__)"], cwd=work, env=env, capture_output=True, text=True,
                           check=True).stdout.split()
    assert all(Path(p).is_relative_to(env_dir) for p in where), where
    toonface = env_dir / "bin" / "toonface"

    def run(*args: str) -> subprocess.CompletedProcess:
        return subprocess.run([toonface, *args], cwd=work, env=env, capture_output=True, text=True, timeout=300)

    demo = run("demo", "--seconds", "1", "--size", "64", "--out", "demo")
    assert demo.returncode == 0, demo.stderr
    assert (work / "demo" / "demo.mp4").stat().st_size > 0
    mapped = run("map", "demo/take.npz", "-o", "motors.csv")
    assert mapped.returncode == 0, mapped.stderr
    assert (work / "motors.csv").read_text().count("\n") > 30
    faces = run("faces")
    assert faces.returncode == 0 and "classic" in faces.stdout.split()
