"""Stubs of ``gyrobias._core.stats`` (binding of ``gyrocore::stats``)."""

__all__ = ["chi2_sf"]

def chi2_sf(x: float, dof: float) -> float: ...
