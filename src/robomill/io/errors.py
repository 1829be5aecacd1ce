"""The error types, re-exported from :mod:`robomill.errors` (where they live), so that
``from robomill.io.errors import RawDataError`` keeps working."""

from robomill.errors import ConfigError, RawDataError

__all__ = ["ConfigError", "RawDataError"]
