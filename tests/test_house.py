"""House rules that can fail: imports point one way, docstring examples run."""

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


@pytest.mark.parametrize("module", ["common.errors", "common.failure", "toon.raster", "player.parts",
                                    "player.layout", "toonface.batch.pairs"])
def test_docstring_examples(module):
    result = doctest.testmod(importlib.import_module(module), optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0 and result.failed == 0
