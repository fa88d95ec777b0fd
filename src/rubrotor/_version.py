"""The package's version, in a module of its own: read it (``rubrotor._version.__version__``)
without importing the package's modules (no import cycle for the layers that record it)."""

__version__ = "0.1.0"
