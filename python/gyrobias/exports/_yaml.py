"""The YAML writer of the estimator files: documents described as items, emitted by ruamel.yaml.

The renderers of :mod:`gyrobias.exports.formats` describe a file as a list of items — a
key with its value and end-of-line comment (:class:`Pair`), a comment line (:class:`Comment`),
a nested mapping (:class:`Block`), a matrix written as rows of flow sequences
(:class:`Matrix`) — and :func:`dump` turns them into text with ruamel.yaml, so no content can
change the document's structure: a string value is quoted by the emitter when it needs to be,
and every comment passes :func:`comment_text`, which escapes anything that would end a comment
line (``\\n``, ``\\r``, ``\\x85``, ``\\u2028``, other control characters, lone surrogates).

Numbers are written with the text each format has always used (``8.333333e-04``, ``200``,
``1.0``), as plain scalars that YAML 1.1 (PyYAML, Kalibr), YAML 1.2 (ruamel) and OpenCV's
``FileStorage`` (OpenVINS, VINS, ORB-SLAM3) read as numbers; the layout (key order, two-space
indentation, ``- [..]`` matrix rows, comments two spaces after the value) is the one the files
had when they were assembled from strings, so the files are byte-identical on ordinary input.

ruamel.yaml is imported when a file is rendered, not with :mod:`gyrobias`.
"""

from __future__ import annotations

import io
from dataclasses import dataclass, field
from typing import Any


@dataclass(frozen=True)
class Pair:
    """``key: value  # comment``; ``value`` is a number (written as ``text``) or a string."""

    key: str
    value: float | str
    text: str | None = None  # the number's text; None for strings
    comment: str | None = None
    quoted: bool = False  # a string written in double quotes whatever its content


@dataclass(frozen=True)
class Comment:
    """A comment line (``# text``) at the indentation of the mapping it belongs to."""

    text: str


@dataclass(frozen=True)
class Block:
    """``key:`` followed by a nested mapping."""

    key: str
    items: list[Any] = field(default_factory=list)


@dataclass(frozen=True)
class Matrix:
    """``key:`` followed by one ``- [a, b, c]`` row per line."""

    key: str
    rows: list[list[str]]


#: One item of a document.
Item = Pair | Comment | Block | Matrix


def comment_text(text: str) -> str:
    """``text`` made safe for a comment line: every character that is not printable (line
    breaks of any kind, control and format characters, lone surrogates) is written as its
    Python escape (``\\n``, ``\\x85``, ``\\u2028``); printable non-ASCII text is kept."""
    return "".join(
        ch if ch.isprintable() else ch.encode("unicode_escape", "backslashreplace").decode("ascii")
        for ch in str(text)
    )


class _Number(float):
    """A float with the exact text it is written as."""

    text: str

    def __new__(cls, value: float, text: str) -> _Number:
        out = super().__new__(cls, value)
        out.text = text
        return out


def _yaml() -> Any:
    try:
        from ruamel.yaml import YAML
    except ImportError as exc:  # a base dependency; a broken install says so in one line
        raise ImportError(
            "writing YAML estimator files needs ruamel.yaml: pip install ruamel.yaml"
        ) from exc
    from ruamel.yaml.nodes import ScalarNode

    yaml = YAML(typ="rt", pure=True)
    yaml.indent(mapping=2, sequence=4, offset=2)
    yaml.width = 1 << 20  # never fold a line
    resolver = yaml.resolver

    def number(representer: Any, data: _Number) -> Any:
        tag = resolver.resolve(ScalarNode, data.text, (True, False))
        if tag not in ("tag:yaml.org,2002:float", "tag:yaml.org,2002:int"):
            raise ValueError(f"{data.text!r} is not a YAML number")
        return representer.represent_scalar(tag, data.text)

    yaml.representer.add_representer(_Number, number)
    return yaml


def _comment_lines(lines: list[str], indent: int) -> str:
    return "".join(f"\n{' ' * indent}# {comment_text(line)}" for line in lines)


def _mapping(items: list[Any], indent: int) -> Any:
    from ruamel.yaml.comments import CommentedMap, CommentedSeq
    from ruamel.yaml.scalarstring import DoubleQuotedScalarString

    out = CommentedMap()
    pending: list[str] = []  # comment lines waiting for the next key
    last: tuple[str, str | None, int] | None = None  # (key, its end-of-line comment, column)
    for item in items:
        if isinstance(item, Comment):
            pending.append(item.text)
            continue
        key = item.key
        if key in out:
            raise ValueError(f"duplicate key {key!r}")
        if isinstance(item, Pair):
            if item.text is not None:
                value: Any = _Number(float(item.value), item.text)
                shown = item.text
            else:
                value = (
                    DoubleQuotedScalarString(str(item.value)) if item.quoted else str(item.value)
                )
                shown = f'"{item.value}"' if item.quoted else str(item.value)
            out[key] = value
            column = indent + len(key) + 2 + len(shown) + 2
            last = (key, item.comment, column)
        elif isinstance(item, Block):
            out[key] = _mapping(item.items, indent + 2)
            last = None
        elif isinstance(item, Matrix):
            rows = CommentedSeq()
            for row in item.rows:
                seq = CommentedSeq([_Number(float(v), v) for v in row])
                seq.fa.set_flow_style()
                rows.append(seq)
            out[key] = rows
            last = None
        else:  # pragma: no cover - the renderers only build the types above
            raise TypeError(f"unknown YAML item {item!r}")
        if pending:
            out.yaml_set_comment_before_after_key(
                key, before="\n".join(comment_text(c) for c in pending), indent=indent
            )
            pending = []
        if isinstance(item, Pair) and item.comment is not None:
            out.yaml_add_eol_comment(f"# {comment_text(item.comment)}", key, column=column)
    if pending:
        # comment lines after the last key: appended to its end-of-line comment
        if last is None:
            raise ValueError("trailing comments need a scalar entry before them")
        key, comment, column = last
        head = "" if comment is None else f"# {comment_text(comment)}"
        out.yaml_add_eol_comment(head + _comment_lines(pending, indent), key, column=column)
    return out


def dump(items: list[Any], *, header: list[str], directive: str | None = None) -> str:
    """The YAML text of ``items``, after the comment lines ``header`` (and the directive line
    ``directive``, e.g. OpenCV's ``%YAML:1.0``, before everything)."""
    yaml = _yaml()
    doc = _mapping(items, 0)
    if header:
        doc.yaml_set_start_comment("\n".join(comment_text(h) for h in header))
    buf = io.StringIO()
    yaml.dump(doc, buf)
    text = buf.getvalue()
    return f"{directive}\n{text}" if directive else text
