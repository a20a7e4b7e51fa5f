"""Shared fixtures. The one place tests create an OpenGL context."""

from __future__ import annotations

from pathlib import Path

import pytest

REALDATA = Path(__file__).resolve().parents[1].parent / "shared" / "realdata"


@pytest.fixture(scope="session")
def gl_context():
    """One EGL context for the whole session (Mesa's llvmpipe here: deterministic)."""
    from player import create_context

    ctx = create_context()
    yield ctx
    ctx.release()


@pytest.fixture
def ctx(gl_context):
    """The session context, checked for GL errors before and after each test."""
    assert gl_context.error == "GL_NO_ERROR"
    yield gl_context
    assert gl_context.error == "GL_NO_ERROR"


@pytest.fixture
def realdata() -> Path:
    """``../shared/realdata``; skips the test, saying why, where it is absent."""
    if not REALDATA.is_dir():
        pytest.skip(f"real-data folder {REALDATA} is absent")
    return REALDATA
