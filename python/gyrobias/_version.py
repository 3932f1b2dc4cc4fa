"""The version of gyrobias (a leaf module: the report and the command line read it without
importing the package façade).

It is the compiled core's version, ``env!("CARGO_PKG_VERSION")``: the workspace version of
``Cargo.toml`` (``[workspace.package]``), the one place a version is set. maturin gives the same
to the wheel and the sdist, so an installed package and a source-tree build
(``scripts/dev-build``) both report it.
"""

from gyrobias._core import __version__

__all__ = ["__version__"]
