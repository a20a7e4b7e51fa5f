"""House rules that can fail: imports point one way between packages and never in a circle
between modules, docstring examples run."""

import ast
import doctest
import importlib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
# Each package and the toonface packages it may import (DESIGN.md: arrows point one way).
ALLOWED = {
    "common": set(),
    "capture": {"common"},
    "toon": {"common"},
    "mapping": {"common", "capture", "toon"},
    "player": {"common", "toon"},
    "stream": {"common", "toon"},
    "toonface": {"common", "capture", "mapping", "toon", "player", "stream"},
}
OURS = set(ALLOWED) | {"bench"}


@pytest.mark.parametrize("package", sorted(ALLOWED))
def test_imports_point_one_way(package):
    bad = []
    for path in sorted((ROOT / package).rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else \
                [node.module or ""] if isinstance(node, ast.ImportFrom) and node.level == 0 else []
            for name in names:
                top = name.split(".")[0]
                if top in OURS and top != package and top not in ALLOWED[package]:
                    bad.append(f"{path.relative_to(ROOT)}:{node.lineno} imports {name}")
    assert not bad, "\n".join(bad)


def _module_imports() -> dict[str, set[str]]:
    """Each module of the packages -> the modules of the packages it imports, at any depth (a
    lazy import inside a function counts: a reader must follow it), ``from a import b`` naming
    module ``a.b`` where there is one."""
    modules = {}
    for package in sorted(ALLOWED):
        for path in sorted((ROOT / package).rglob("*.py")):
            parts = path.relative_to(ROOT).with_suffix("").parts
            modules[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path

    def resolve(name: str) -> str | None:
        while name and name not in modules:
            name = name.rpartition(".")[0]
        return name or None

    graph: dict[str, set[str]] = {}
    for module, path in modules.items():
        here = module if path.name == "__init__.py" else module.rpartition(".")[0]
        graph[module] = set()
        for node in ast.walk(ast.parse(path.read_text())):
            names: list[str] = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    parts = here.split(".")
                    base = ".".join(parts[:len(parts) - node.level + 1] + ([base] if base else []))
                names = [base, *(f"{base}.{a.name}" for a in node.names)]
            for name in names:
                target = resolve(name)
                # a package's __init__ importing its own modules, or a module its package: not a circle
                if target and target != module and not module.startswith(target + "."):
                    graph[module].add(target)
    return graph


def _circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on.add(root)
        while work:
            node, edges = work[-1]
            step = next(edges, None)
            if step is not None:
                if step not in index:
                    index[step] = low[step] = len(index)
                    stack.append(step)
                    on.add(step)
                    work.append((step, iter(sorted(graph[step]))))
                elif step in on:
                    low[node] = min(low[node], index[step])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                part = []
                while True:
                    top = stack.pop()
                    on.discard(top)
                    part.append(top)
                    if top == node:
                        break
                if len(part) > 1:
                    out.append(sorted(part))
    return out


def test_no_import_circles_between_modules():
    assert _circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]  # the check can fail
    assert not _circles({"a": {"b"}, "b": set()})
    circles = _circles(_module_imports())
    assert not circles, "import circles: " + "; ".join(", ".join(c) for c in circles)


def _modules_with_examples() -> list[str]:
    """Every module of the packages whose source has a docstring example (``>>>``), found by
    walking the folders: a new example is tested without being listed anywhere."""
    found = []
    for package in sorted(ALLOWED):
        for path in sorted((ROOT / package).rglob("*.py")):
            if ">>> " in path.read_text() and path.name != "__main__.py":
                parts = path.relative_to(ROOT).with_suffix("").parts
                found.append(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return found


@pytest.mark.parametrize("module", _modules_with_examples())
def test_docstring_examples(module):
    result = doctest.testmod(importlib.import_module(module), optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0 and result.failed == 0


def test_the_examples_are_found():
    found = _modules_with_examples()
    assert {"common.errors", "common.validate", "player.parts", "toonface.batch.pairs"} <= set(found), found


_COUNT_OPENS = """
import collections, sys
opened = collections.Counter()
def hook(event, args):
    if event == "open" and isinstance(args[0], str) and not any(m in str(args[1] or "r") for m in "wax+"):
        opened[args[0]] += 1
sys.addaudithook(hook)
from toonface.cli import main
code = main(sys.argv[1:])
print(repr(dict(opened)))
sys.exit(code)
"""


@pytest.mark.gl
@pytest.mark.slow
@pytest.mark.parametrize("extra", [["--calibrate", "take.npz"], ["--mapping", "toon32", "--face", "round"]])
def test_a_retarget_reads_no_file_twice(tmp_path, extra):
    """One `retarget --calibrate` opened markersets/toon32.toml four times, mappings/toon32.toml
    twice and the take twice; every file it reads (built-in data, the user's take) is read once."""
    import subprocess
    import sys

    from capture import save_take, synthesize

    save_take(synthesize(seconds=1.0, rate=30.0).take, tmp_path / "take.npz")
    run = subprocess.run([sys.executable, "-c", _COUNT_OPENS, "retarget", "take.npz", "-o", "out.mp4",
                          "--size", "32x32", *extra], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    opened = ast.literal_eval(run.stdout.strip().splitlines()[-1])
    ours = {path: n for path, n in opened.items() if not path.endswith((".py", ".pyc", ".pyi"))
            and not path.startswith(("/dev/", "/proc/", sys.base_prefix, sys.prefix)) and "dist-info" not in path}
    assert any(path.endswith("toon32.toml") for path in ours) and "take.npz" in ours
    assert {path: n for path, n in ours.items() if n > 1} == {}, ours


def _toml(doc: dict) -> str:
    import tomli_w

    return tomli_w.dumps(doc)


@pytest.mark.parametrize("kind", ["markerset", "mapping", "profile", "performance", "face", "expressions", "job"])
def test_every_file_kind_words_a_bad_field_alike(tmp_path, kind):
    """Five validators had four wordings ('unknown key', 'unknown keys [...]', 'unknown field(s)',
    'unexpected field(s)'); one validator now says `FILE: field.path: what is wrong` for all."""
    import json
    import tomllib

    from capture import load_markerset
    from capture.performance import load_performance
    from common import InputError, data_path
    from mapping import load_mapping, load_profile
    from toon import load_expressions, load_face
    from toonface.batch import load_job

    def builtin(*parts):
        path = data_path(*parts)
        return json.loads(path.read_text()) if path.suffix == ".json" else tomllib.loads(path.read_text())

    if kind == "markerset":
        doc, nested = builtin("markersets", "toon32.toml"), "markers.LID_R_UP"
        doc["markers"]["LID_R_UP"]["colour"] = "red"
    elif kind == "mapping":
        doc, nested = builtin("mappings", "toon32.toml"), "motor.ERU"
        doc["motor"]["ERU"]["colour"] = "red"
    elif kind == "profile":
        doc, nested = builtin("profiles", "toon32.toml"), 'sources."LID_R_UP.y"'
        doc["sources"]["LID_R_UP.y"]["colour"] = "red"
    elif kind == "performance":
        doc, nested = {"format": "toonface.performance/1", "seconds": 2,
                               "cue": [{"kind": "blink", "start": 0, "colour": "red"}]}, "cue[0]"
    elif kind == "face":
        doc, nested = builtin("faces", "classic.json"), "polygons[0]"
        doc["polygons"][0]["colour"] = "red"
    elif kind == "expressions":
        doc, nested = builtin("expressions.toml"), "expressions.happiness"
        doc["expressions"]["happiness"]["colour"] = "red"
    else:
        (tmp_path / "a.npz").write_bytes(b"")
        doc, nested = {"format": "toonface.batch/1", "takes": ["a.npz"], "faces": ["classic"],
                               "render": {"size": "64", "colour": "red"}}, "render"
    suffix = ".json" if kind == "face" else ".toml"
    path = tmp_path / f"bad{suffix}"
    path.write_text(json.dumps(doc) if suffix == ".json" else _toml(doc))
    load = {"markerset": load_markerset, "mapping": load_mapping, "profile": load_profile,
            "performance": load_performance, "face": load_face, "expressions": load_expressions,
            "job": load_job}[kind]
    with pytest.raises(InputError) as caught:
        load(path)
    message = str(caught.value)
    assert message.startswith(f"{path}: {nested}.colour: unknown field (known: "), message
    assert message.count("\n") == 0
