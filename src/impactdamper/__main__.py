"""``python -m impactdamper``: see :mod:`impactdamper.cli`."""

from .cli import run

raise SystemExit(run())
