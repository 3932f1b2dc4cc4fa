"""Stubs of ``gyrobias._core.validate`` (binding of ``gyrocore::validate``)."""

__all__ = ["sample_period"]

def sample_period(fs: float) -> float: ...
