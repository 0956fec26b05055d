"""``python -m impactdamper``: see :mod:`impactdamper.cli`."""

from .cli import main

raise SystemExit(main())
