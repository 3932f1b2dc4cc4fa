"""The installed version of gyrobias (a leaf module: the report and the command line read it
without importing the package façade)."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("gyrobias")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0+unknown"

__all__ = ["__version__"]
