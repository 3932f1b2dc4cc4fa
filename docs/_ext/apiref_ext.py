"""Sphinx hook: write ``api/index.rst`` from :mod:`apiref` before the sources are read."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import apiref


def _on_config_inited(app: Any, config: Any) -> None:
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
    # config-inited: before the environment lists the source files (and autosummary scans them)
    app.connect("config-inited", _on_config_inited)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
