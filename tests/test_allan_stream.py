"""Out-of-core overlapping ADEV (issue 12 item 5): a memory-mapped ``.npy`` is streamed through the
core in pieces read from the file, with results identical to the in-memory call (bit for bit,
with a forced small read size that lines up with none of the kernel's blocks)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gyrobias import allan
from gyrobias.allan import stream

FIELDS = ("taus", "avar", "n_terms", "edf", "alpha", "ci_low", "ci_high", "noise_type", "axis")


def _same(a: allan.AllanResult, b: allan.AllanResult) -> None:
    for field in FIELDS:
        x, y = getattr(a, field), getattr(b, field)
        if isinstance(x, np.ndarray):
            np.testing.assert_array_equal(x, y, err_msg=field)
        else:
            assert x == y, field


@pytest.fixture
def small_reads(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """Force 1 000-sample reads and count them."""
    monkeypatch.setattr(stream, "_STREAM_BLOCK", 1000)
    calls: list[int] = []
    original = stream._ColumnReader.__call__

    def counted(self: stream._ColumnReader, start: int, count: int) -> np.ndarray:
        calls.append(count)
        return original(self, start, count)

    monkeypatch.setattr(stream._ColumnReader, "__call__", counted)
    return calls


def _log(n: int, axes: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.normal(0.3, 1.0, (n, axes)) + np.cumsum(rng.normal(0.0, 2e-3, (n, axes)), axis=0)


@pytest.mark.parametrize("dtype", ["<f8", ">f8", "<f4"])
@pytest.mark.parametrize("data_type", ["rate", "angle"])
def test_memmap_equals_in_memory(
    tmp_path: Path, small_reads: list[int], dtype: str, data_type: str
) -> None:
    data = _log(300_001, 3).astype(dtype)
    path = tmp_path / "log.npy"
    np.save(path, data)
    mapped = np.load(path, mmap_mode="r")
    assert isinstance(mapped, np.memmap)
    streamed = allan.adev(mapped, 100.0, taus="log", data_type=data_type, axis_names="xyz")
    assert max(small_reads) <= 1000 and len(small_reads) > 300  # it did stream
    memory = allan.adev(np.array(data), 100.0, taus="log", data_type=data_type, axis_names="xyz")
    for a, b in zip(streamed, memory):
        _same(a, b)


def test_memmap_views_and_one_axis(tmp_path: Path, small_reads: list[int]) -> None:
    data = _log(200_000, 4, seed=1)
    path = tmp_path / "log.npy"
    np.save(path, data)
    mapped = np.load(path, mmap_mode="r")
    view = mapped[1234:, 1:3]  # offset rows, strided columns: still read from the file
    streamed = allan.adev(view, 50.0, confidence=0.95)
    memory = allan.adev(np.ascontiguousarray(data[1234:, 1:3]), 50.0, confidence=0.95)
    for a, b in zip(streamed, memory):
        _same(a, b)
    single = allan.adev(mapped[:, 2], 50.0, confidence=None)
    assert isinstance(single, allan.AllanResult)
    _same(single, allan.adev(np.ascontiguousarray(data[:, 2]), 50.0, confidence=None))
    assert small_reads


def test_memmap_progress_and_other_estimators(tmp_path: Path, small_reads: list[int]) -> None:
    data = _log(100_000, 1, seed=2)[:, 0]
    path = tmp_path / "log.npy"
    np.save(path, data)
    mapped = np.load(path, mmap_mode="r")
    seen: list[float] = []
    streamed = allan.adev(mapped, 10.0, progress=seen.append)
    assert isinstance(streamed, allan.AllanResult)
    assert seen[0] == 0.0 and seen[-1] == 1.0 and seen == sorted(seen)
    _same(streamed, allan.adev(np.array(data), 10.0))
    # Estimators that are not streamed read the mapping in memory: same numbers as ever.
    for f in (allan.mdev, allan.hdev):
        a, b = f(mapped, 10.0), f(np.array(data), 10.0)
        assert isinstance(a, allan.AllanResult) and isinstance(b, allan.AllanResult)
        _same(a, b)


def test_memmap_bad_values_are_located(tmp_path: Path, small_reads: list[int]) -> None:
    data = _log(50_000, 1)[:, 0]
    data[33_333] = np.inf
    path = tmp_path / "log.npy"
    np.save(path, data)
    with pytest.raises(ValueError, match="index 33333"):
        allan.adev(np.load(path, mmap_mode="r"), 10.0)
