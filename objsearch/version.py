"""``__version__``: the installed distribution's version, or ``0.0.0+unknown`` in a source tree
that is not installed. ``objsearch.__version__`` is this; code that records the version
(``objsearch.eval.results``) reads it here, not through the package, whose ``__init__`` imports
the Python API (``objsearch.api``) on first use."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("objsearch")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0.0.0+unknown"
