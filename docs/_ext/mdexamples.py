"""Run the ```python examples of Markdown pages (doctest form, ``>>>``) — in the build and in pytest.

Every fenced block whose info string is ``python`` (or ``pycon``) and whose first non-blank line
starts with ``>>>`` is an example. The blocks of one page run in order in one namespace (a page
is one story), in a fresh temporary directory as the working directory (files the page writes
go there), with matplotlib's non-interactive Agg backend. Output is compared by :mod:`doctest`
with ``ELLIPSIS`` and ``NORMALIZE_WHITESPACE``.

A shell block whose info string is ``bash run`` is a command-line example: each of its
``gyrobias …`` lines runs (through :func:`gyrobias.cli.main`, in the same directory, after the
blocks above it) and must exit with 0. Other shell blocks are shown, not run (placeholders such
as ``LOG`` or commands of other tools).

The Sphinx extension part runs each Markdown page when Sphinx reads it and reports a failing
example as a warning at the page's line (an error under ``-W``); ``tests/test_docs_pages.py``
runs the same function on every ``docs/**/*.md`` and on the README.
"""

from __future__ import annotations

import doctest
import os
import re
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

FENCE = re.compile(r"^(?P<fence>```+|~~~+)\s*(?P<info>[^\n`]*)$")
LANGUAGES = {"python", "pycon", "py"}
FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def extract(text: str, languages: set[str] = LANGUAGES) -> list[tuple[int, str]]:
    """The doctest blocks of a Markdown text: ``(first line number (1-based), source)``."""
    return [(ln, src) for ln, kind, src in blocks_of(text, languages) if kind == "doctest"]


def commands(text: str) -> list[tuple[int, str]]:
    """The ``gyrobias …`` lines of the ``bash run`` blocks: ``(line number, command)``."""
    return [(ln, src) for ln, kind, src in blocks_of(text) if kind == "command"]


def blocks_of(text: str, languages: set[str] = LANGUAGES) -> list[tuple[int, str, str]]:
    """Doctest blocks and command lines in page order: ``(line number, kind, source)``."""
    blocks: list[tuple[int, str, str]] = []
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i].strip())
        if m is None:
            i += 1
            continue
        fence = m.group("fence")
        info = m.group("info").strip().split()
        lang = info[0].strip("{}") if info else ""
        start = i + 1
        j = start
        while j < len(lines) and not lines[j].strip().startswith(fence):
            j += 1
        body = lines[start:j]
        first = next((ln for ln in body if ln.strip()), "")
        if lang in languages and first.lstrip().startswith(">>>"):
            indent = len(first) - len(first.lstrip())
            blocks.append((start + 1, "doctest", "\n".join(ln[indent:] for ln in body) + "\n"))
        elif lang in {"bash", "sh", "console"} and "run" in info[1:]:
            for k, ln in enumerate(body):
                cmd = ln.strip().split(" #")[0].strip()
                if cmd.startswith("gyrobias "):
                    blocks.append((start + 1 + k, "command", cmd))
        i = j + 1
    return blocks


@dataclass
class PageResult:
    """Outcome of one page: examples attempted, failures (line, report), seconds."""

    path: str
    attempted: int
    failures: list[tuple[int, str]]
    seconds: float


class _Collect(doctest.DocTestRunner):
    def __init__(self) -> None:
        super().__init__(optionflags=FLAGS, verbose=False)
        self.reports: list[tuple[int, str]] = []

    def report_failure(
        self, out: Any, test: doctest.DocTest, example: doctest.Example, got: str
    ) -> None:
        line = (test.lineno or 0) + example.lineno + 1
        self.reports.append(
            (line, f"{example.source.strip()}\nexpected:\n{example.want}got:\n{got}")
        )

    def report_unexpected_exception(
        self, out: Any, test: doctest.DocTest, example: doctest.Example, exc_info: Any
    ) -> None:
        line = (test.lineno or 0) + example.lineno + 1
        exc = doctest._exception_traceback(exc_info)  # type: ignore[attr-defined]
        self.reports.append((line, f"{example.source.strip()}\nraised:\n{exc}"))


def run_text(
    text: str,
    name: str,
    *,
    setup: Callable[[Path], None] | None = None,
    globs: dict[str, Any] | None = None,
) -> PageResult:
    """Run every example block of ``text`` in a temporary working directory."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    start = time.perf_counter()
    parser = doctest.DocTestParser()
    runner = _Collect()
    namespace: dict[str, Any] = {"__name__": "__docs__"} if globs is None else dict(globs)
    attempted = 0
    old = os.getcwd()
    with tempfile.TemporaryDirectory(prefix="gyrobias-docs-") as tmp:
        os.chdir(tmp)
        try:
            if setup is not None:
                setup(Path(tmp))
            for lineno, kind, source in blocks_of(text):
                if kind == "command":
                    attempted += 1
                    _run_command(source, lineno, runner.reports)
                    continue
                try:
                    test = parser.get_doctest(source, namespace, name, name, lineno - 1)
                except ValueError as exc:  # malformed doctest text: a failure, not a crash
                    runner.reports.append((lineno, f"cannot parse the example block: {exc}"))
                    continue
                test.globs = namespace  # one namespace for the page (get_doctest copies)
                result = runner.run(test, clear_globs=False)
                attempted += result.attempted
        finally:
            os.chdir(old)
            import matplotlib.pyplot as plt

            plt.close("all")
    return PageResult(name, attempted, runner.reports, time.perf_counter() - start)


def _run_command(command: str, lineno: int, reports: list[tuple[int, str]]) -> None:
    """Run one ``gyrobias …`` line through the CLI's ``main``; a non-zero exit is a failure."""
    import contextlib
    import io
    import shlex

    from gyrobias.cli import main

    out, err = io.StringIO(), io.StringIO()
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(shlex.split(command)[1:])
    except SystemExit as exc:  # argparse usage errors
        code = exc.code if isinstance(exc.code, int) else 2
    if code != 0:
        reports.append((lineno, f"{command}\nexit code {code}:\n{err.getvalue()[-2000:]}"))


def run_file(path: str | os.PathLike[str], **kwargs: Any) -> PageResult:
    """Run the examples of one Markdown file."""
    p = Path(path)
    return run_text(p.read_text(encoding="utf-8"), str(p), **kwargs)


# ----------------------------------------------------------------------------- Sphinx part


def _on_source_read(app: Any, docname: str, source: list[str]) -> None:
    from sphinx.util import logging

    path = Path(app.env.doc2path(docname))
    if path.suffix != ".md":
        return
    text = source[0]
    if not blocks_of(text):
        return
    logger = logging.getLogger("gyrobias.mdexamples")
    result = run_text(text, str(path))
    app.env.gyrobias_examples = getattr(app.env, "gyrobias_examples", {})
    app.env.gyrobias_examples[docname] = (result.attempted, result.seconds)
    for line, report in result.failures:
        logger.warning("example failed:\n%s", report, location=(docname, line))
    logger.info("[examples] %s: %d examples, %.1f s", docname, result.attempted, result.seconds)


def setup(app: Any) -> dict[str, Any]:
    app.connect("source-read", _on_source_read)
    return {"parallel_read_safe": False, "parallel_write_safe": True}
