"""Take the screenshots of docs/guides/explore.md at every build (``make docs``).

Before Sphinx reads the pages, ``docs/_tools/explore_screenshots.py`` serves ``gyrobias explore``
over simulated logs on the loopback address and photographs each view in headless Chromium
(Playwright driving the system browser), into ``docs/guides/_explore/`` (not committed). A
failure (no Chromium, a view that shows an error) stops the build: the guide's pictures are
always the current app's.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

TOOL = Path(__file__).resolve().parents[1] / "_tools" / "explore_screenshots.py"


def _shoot(app: Any) -> None:
    out = Path(app.srcdir) / "guides" / "_explore"
    done = subprocess.run(
        [sys.executable, str(TOOL), str(out)], capture_output=True, text=True, timeout=900
    )
    if done.returncode != 0:
        tail = "\n".join((done.stderr or done.stdout).strip().splitlines()[-15:])
        raise RuntimeError(f"explore screenshots failed:\n{tail}")


def setup(app: Any) -> dict[str, Any]:
    app.connect("builder-inited", _shoot)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
