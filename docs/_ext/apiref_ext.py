"""Sphinx hook: write ``api/index.rst`` from :mod:`apiref` before the sources are read."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import apiref


def _on_builder_inited(app: Any) -> None:
    from sphinx.util import logging

    text, unplaced = apiref.render()
    target = Path(app.srcdir) / "api" / "index.rst"
    target.parent.mkdir(exist_ok=True)
    if not target.exists() or target.read_text(encoding="utf-8") != text:
        target.write_text(text, encoding="utf-8")
    if unplaced:
        logging.getLogger("gyrobias.apiref").info(
            "[apiref] names not placed in a task group (listed under 'Other public names'): %s",
            ", ".join(unplaced),
        )


def setup(app: Any) -> dict[str, Any]:
    app.connect("builder-inited", _on_builder_inited)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
