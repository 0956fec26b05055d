#!/usr/bin/env bash
# Sets up a machine for the project, in the project's own virtual environment `.venv/`:
#   - .venv/ from a python3 >= 3.11 (Debian's or Ubuntu's own /usr/bin/python3 refuses
#     `pip install` outside a venv, PEP 668; a pyenv or conda python works the same way here);
#     where `python3 -m venv` is missing on Debian/Ubuntu, python3-venv comes from apt;
#   - the pinned Python packages (requirements.txt) and this package in editable mode;
#   - a Jupyter kernel `python3` inside the venv, for the notebooks;
#   - TeX Live and poppler from Debian's packages for the report, and Siconos
#     (python3-siconos, for Debian's /usr/bin/python3) for one column of the work-precision
#     study, when apt is there.
# Safe to run again: an existing, working .venv/ is reused and only topped up.
# Choose the interpreter with PYTHON=/path/to/python3 (default: python3 on PATH).
set -euo pipefail
cd "$(dirname "$0")/.."

PYTHON="${PYTHON:-python3}"
VENV=.venv
SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
apt_updated=0
apt_install() {  # apt_install PACKAGE...: Debian's packages, quietly; one `apt-get update` per run
  command -v apt-get >/dev/null || return 1
  if [ "$apt_updated" = 0 ]; then $SUDO apt-get update -qq && apt_updated=1; fi
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "$@" >/dev/null
}

command -v "$PYTHON" >/dev/null || { echo "setup: $PYTHON not found; install Python >= 3.11 or set PYTHON=" >&2; exit 1; }
if ! "$PYTHON" -c 'import sys; sys.exit(sys.version_info < (3, 11))'; then
  echo "setup: $("$PYTHON" --version 2>&1) is too old; Python >= 3.11 is needed (set PYTHON=)" >&2
  exit 1
fi

# A venv made by another interpreter, or half-made by an interrupted run, is made anew.
if [ -x "$VENV/bin/python" ] && ! "$VENV/bin/python" -m pip --version >/dev/null 2>&1; then
  echo "setup: $VENV is broken; making it anew"
  rm -rf "$VENV"
fi
if [ ! -x "$VENV/bin/python" ]; then
  if ! "$PYTHON" -m venv "$VENV" 2>/dev/null; then
    rm -rf "$VENV"
    # Debian and Ubuntu ship venv (with ensurepip) apart from python3: python3.X-venv.
    pyver=$("$PYTHON" -c 'import sys; print(f"{sys.version_info[0]}.{sys.version_info[1]}")')
    echo "setup: $PYTHON -m venv is missing; installing python${pyver}-venv from apt"
    apt_install "python${pyver}-venv" || apt_install python3-venv \
      || { echo "setup: cannot make a virtual environment: install python3-venv" >&2; exit 1; }
    "$PYTHON" -m venv "$VENV"
  fi
  echo "setup: made $VENV with $("$VENV/bin/python" --version)"
fi

PIP=("$VENV/bin/python" -m pip --quiet --disable-pip-version-check)
"${PIP[@]}" install -r requirements.txt
"${PIP[@]}" install --no-deps -e .
# The notebooks' kernel `python3`, in the venv (the workflow puts .venv/share/jupyter first on
# JUPYTER_PATH, so a user-wide kernel of the same name cannot take its place).
"$VENV/bin/python" -m ipykernel install --sys-prefix --name python3 >/dev/null

need_tex=0
for cmd in latexmk pdflatex pdftoppm; do command -v "$cmd" >/dev/null || need_tex=1; done
if [ "$need_tex" = 1 ]; then
  apt_install latexmk texlive-latex-base texlive-latex-recommended texlive-latex-extra \
    texlive-fonts-recommended poppler-utils \
    || { echo "setup: TeX Live could not be installed (latexmk, pdflatex and pdftoppm are needed for the report)" >&2; exit 1; }
fi
# Siconos's Moreau-Jean time-stepping, a baseline of the work-precision study. Debian packages
# its Python module for Debian's own /usr/bin/python3 (~64 MB download, ~475 MB installed,
# ~30 s); the study runs it there in a subprocess. Optional: where apt or the package is
# missing the study says plainly that Siconos was not available.
if command -v apt-get >/dev/null && [ -x /usr/bin/python3 ] && ! /usr/bin/python3 -c "import siconos.kernel" 2>/dev/null; then
  if apt_install python3-siconos 2>/dev/null; then
    echo "setup: Siconos installed for /usr/bin/python3"
  else
    echo "setup: python3-siconos not installed (optional; the work-precision study will say so)"
  fi
fi
# The compiled solver's numba kernels, compiled once into numba's on-disk cache beside the
# sources (about a minute on two cores), as a C extension would be built at install: the
# workflow's and the tests' first jobs then load them (about a second) instead of compiling.
# The workflow's rule compiled_warm_up still compiles them where the cache is missing or stale.
"$VENV/bin/python" -c "from impactdamper.core.backends import warm_up; print(f'setup: compiled kernels ready in {warm_up():.0f} s')"
# Their compile time from scratch (into an empty cache of its own, then loaded from it), measured
# once here for the report (results/setup/compile_time.json), not in every workflow run; measured
# again only when the kernels' sources or numba changed since (another minute or two).
"$VENV/bin/python" - <<'PY'
from impactdamper.studies.performance.compile_record import current_compile_record, write_compile_record

path = "results/setup/compile_time.json"
if current_compile_record(path):
    print(f"setup: the kernels' compile time is on record ({path})")
else:
    c = write_compile_record(path)["compile"]
    print(f"setup: the kernels' compile time measured: {c['cold_compile_s']:.0f} s from scratch, "
          f"{c['cached_load_s']:.1f} s from the cache ({path})")
PY
echo "setup: done; the project's interpreter is $VENV/bin/python"
