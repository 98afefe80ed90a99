"""kincalc's version (the same as pyproject.toml's; tests/test_architecture.py checks it)."""

__version__ = "0.1.0"
