"""Command line: ``impactdamper {steady,alg1,orbit,response,design,lyapunov} [--PARAM VALUE ...] [--json]``.

The same as ``python -m impactdamper ...``; ``impactdamper`` is the console script the package
installs (pyproject.toml, ``[project.scripts]``).

Every parameter of :class:`impactdamper.Parameters` is a flag (defaults: the paper's reference
case). A bad value exits with status 2 and a one-line message naming the flag; so does a case
beyond what the solver can do (an undamped resonance, a motion too fast for its work bound),
naming the parameter that makes it so. Output that cannot be written (a closed pipe, a full
disk) ends with one line on stderr and status 1.

Its modules, one idea each: :mod:`~impactdamper.cli.parser` (the flags and their help),
:mod:`~impactdamper.cli.commands` (each command run, the checks argparse cannot make),
:mod:`~impactdamper.cli.output` (the answers as text or JSON, write failures) and
:mod:`~impactdamper.cli.process` (the process around them).
"""

from impactdamper.cli.commands import main
from impactdamper.cli.parser import PARAMETER_HELP, PROG, add_quiet_flag, build_parser
from impactdamper.cli.process import run

__all__ = ["main", "run", "build_parser", "add_quiet_flag", "PROG", "PARAMETER_HELP"]
