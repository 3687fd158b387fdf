"""The package's version (one place: the package's __init__ and the benchmarks read it here)."""

__version__ = "0.1.0"
