"""The command-line convention of every ``python -m`` command of the project (one home).

``common`` is the ground floor of the layers (``common`` -> ``mdr`` -> ``meshes`` -> ``fem`` ->
``studies`` -> ``validation``), so the shared CLI pieces live here and ``python -m mdr``,
``python -m fem`` and ``python -m validation.compare`` use them:

- :class:`OneLineParser`: argparse whose usage errors are one line on stderr,
  exit code 2;
- :func:`run_command`: parse, check the output paths before the (costly) run,
  run ``args.func(args)``, write its result as JSON to ``--json`` (``-`` =
  stdout, the default); bad input (``InputError``) exits 2 with
  ``<prog> <command>: error: <message>``, a solver that does not converge
  (``ConvergenceError``) exits 3 with ``<prog> <command>: solver failed: <message>``.
  A command that writes its own output (``write_result=False``, e.g.
  ``validation.compare``) returns its exit code instead of a result.
"""
from __future__ import annotations

import argparse
import re
import sys

from .errors import ConvergenceError, InputError
from .io import check_output_dir, check_output_path, write_json

#: the flags that name an output file, checked before the run
OUTPUT_FLAGS = ("json", "vtu")
#: the flags that name an output folder, checked before the run
OUTPUT_DIR_FLAGS = ("out",)


#: a negative number as an option value, exponents included (argparse's own pattern misses
#: ``-6e-3``, so ``--R -6e-3`` would read as a missing value instead of reaching the range check)
NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-inf$|^-nan$", re.IGNORECASE)


#: what to cite, printed by every command's ``--version`` (CITATION.cff holds the same)
CITE = ("Cite this software (CITATION.cff) and the experiment and model it follows: Willert, E., Influence of "
        "Profile Geometry on Frictional Energy Dissipation in a Dry, Compliant Steel-on-Steel Fretting "
        "Contact: Macroscopic Modeling and Experiment, Machines 11 (2023) 484, doi:10.3390/machines11040484; "
        "the method: Popov, V. L. and Hess, M., Method of Dimensionality Reduction in Contact Mechanics and "
        "Friction, Springer (2015).")


def version_text() -> str:
    """The installed package's name and version (its metadata: pyproject.toml's ``version``) and what
    to cite."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        v = version("fretting-mdr-fem")
    except PackageNotFoundError:
        v = "(not installed: pip install -e .)"
    return f"fretting-mdr-fem {v}\n{CITE}"


class _Version(argparse.Action):
    """``--version``: ``version_text`` as it is (argparse's own action reflows it), exit 0."""

    def __call__(self, parser, namespace, values, option_string=None):
        sys.stdout.write(version_text() + "\n")
        parser.exit(0)


class OneLineParser(argparse.ArgumentParser):
    """argparse parser whose errors are one line on stderr and exit code 2, which reads a negative
    number (``-6e-3``) as a value, not as an option, and whose ``--version`` says what to cite."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = NEGATIVE_NUMBER
        self.add_argument("--version", action=_Version, nargs=0, help="print the version and what to cite, and exit")

    def error(self, message):
        sys.stderr.write(f"{self.prog}: error: {message}\n")
        sys.exit(2)


def add_output_args(p):
    """``--json PATH`` (default stdout)."""
    p.add_argument("--json", default="-", metavar="PATH", help="write the result as JSON to PATH ('-' = stdout, default)")


def run_command(parser: argparse.ArgumentParser, argv=None, *, write_result: bool = True,
                check_outputs: bool = True) -> int:
    """Run the subcommand ``args.func`` of ``parser`` with the exit codes of the module docstring.

    ``write_result=False``: ``args.func`` writes its own output and returns the exit code
    (``None`` = 0) instead of a result to write to ``--json``. ``check_outputs=False``: ``args.func``
    checks its output paths itself, after its inputs (a refused input then creates no output folder)."""
    args = parser.parse_args(argv)
    where = " ".join(filter(None, (parser.prog, getattr(args, "command", None))))
    try:
        for flag in OUTPUT_FLAGS if check_outputs else ():
            path = getattr(args, flag, None)
            if path not in (None, "-"):
                check_output_path(path, "--" + flag)
        for flag in OUTPUT_DIR_FLAGS if check_outputs else ():
            path = getattr(args, flag, None)
            if path is not None and not getattr(args, "list", False):  # --list writes nothing
                check_output_dir(path, "--" + flag)
        result = args.func(args)
        if not write_result:
            return result or 0
        _note_stationarity(where, result)
        if getattr(args, "json", None) is not None:
            write_json(args.json, result)
    except InputError as exc:
        sys.stderr.write(f"{where}: error: {exc}\n")
        return 2
    except ConvergenceError as exc:
        sys.stderr.write(f"{where}: solver failed: {exc}\n")
        return 3
    return 0


def _note_stationarity(where: str, result) -> None:
    """One line on stderr where a result's last cycle is not stationary (its ``cycle_change``), naming
    the flag that helps; the result itself carries the change (JSON keys ``stationary``,
    ``cycle_change``)."""
    if not isinstance(result, dict) or result.get("stationary") is not False:
        return
    ch = result.get("cycle_change") or {}
    fmt = lambda x: "-" if x is None else f"{x:.2g}"  # noqa: E731
    cycles = (result.get("inputs") or {}).get("cycles", "the")
    sys.stderr.write(f"{where}: note: the last of {cycles} cycles is not stationary (loop change "
                     f"{fmt(ch.get('loop'))}, dissipation change {fmt(ch.get('dissipation'))}); "
                     "more --cycles settle it\n")
