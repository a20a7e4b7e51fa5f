"""MkDocs hooks for the site (mkdocs.yml ``hooks``): the docstrings' Sphinx roles as plain code.

The docstrings are numpydoc, written to read well in a terminal too, and name other objects with
Sphinx roles (``:func:`render```, ``:class:`~common.errors.Interrupted```); mkdocstrings shows the
role's text as it is. This turns each into the code it names, as ``help()`` readers read it.
"""

from __future__ import annotations

import re

_ROLE = re.compile(r":(?:func|class|meth|mod|data|attr|exc|obj):(<code>)~?")


def on_page_content(html: str, **_: object) -> str:
    """The page's HTML with ``:role:<code>~name`` written as ``<code>name``."""
    return _ROLE.sub(r"\1", html)
