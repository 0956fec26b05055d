"""numba's cache of the kernels, kept in step with the sources they are compiled from.

numba checks a cached kernel against its own file only: a kernel compiled with a function of
another file inlined or linked into it (the march into the event loop, the loop into the settled
motion), or with a constant of the reference solver frozen into it (``MAX_STEPS``,
``REBASE_PERIODS``), stays in the cache when that other file changes, and would run the old code
without a word. So the cache is stamped with a digest of every source of :mod:`impactdamper.core`
(the kernels and the reference modules whose constants they read); where the stamp differs, the
cached kernels are removed before any is loaded, and they compile afresh.

Only numba's default cache beside the sources (``__pycache__``) is kept so; with
``NUMBA_CACHE_DIR`` set, the user's cache directory is the user's to clear.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

# The stamp, beside the cached kernels.
STAMP_NAME = "sources.sha256"


def _sources_digest(sources: list[Path]) -> str:
    """sha256 over the files' names (with their folder's, not where the checkout lies) and
    contents, in that order."""
    h = hashlib.sha256()
    for path in sorted(sources, key=lambda q: (q.parent.name, q.name)):
        h.update(f"{path.parent.name}/{path.name}".encode())
        h.update(b"\0")
        h.update(path.read_bytes())
    return h.hexdigest()


def _clear_if_stale(cache_dir: Path, sources: list[Path]) -> bool:
    """Remove numba's cached kernels (``*.nbi``, ``*.nbc``) from ``cache_dir`` unless its stamp
    matches the sources' digest, then stamp it. Returns whether it removed any. A directory it
    cannot write is left as it is (numba then caches elsewhere)."""
    digest = _sources_digest(sources)
    stamp = cache_dir / STAMP_NAME
    try:
        if stamp.is_file() and stamp.read_text().strip() == digest:
            return False
        removed = False
        if cache_dir.is_dir():
            for f in list(cache_dir.glob("*.nbi")) + list(cache_dir.glob("*.nbc")):
                f.unlink(missing_ok=True)
                removed = True
        cache_dir.mkdir(parents=True, exist_ok=True)
        tmp = cache_dir / f"{STAMP_NAME}.{os.getpid()}"
        tmp.write_text(digest + "\n")
        tmp.replace(stamp)  # (atomic: a parallel process reads the old stamp or the new one)
        return removed
    except OSError:
        return False


def keep_in_step() -> bool:
    """:func:`clear_if_stale` for this package's kernels, unless ``NUMBA_CACHE_DIR`` is set."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return False
    here = Path(__file__).resolve().parent
    sources = sorted(here.glob("*.py")) + sorted(here.parent.glob("*.py"))
    return _clear_if_stale(here / "__pycache__", sources)
