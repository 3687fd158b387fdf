"""The ``polhode`` command line: ``polhode demo``, ``polhode spin``, ``polhode inertia``,
``polhode audit`` and ``polhode bench``; a bare ``polhode`` prints the help, and on stderr that
no command was given, and exits with status 2 (a usage error, as argparse has it), writing
nothing.

One module per command (``demo``, ``spin``, ``inertia``, ``audit``, ``bench``: each has its
``run(args)``), the parser apart (``_parser``), and what they share in ``_common`` (UsageError,
the number types, the checks of output files, ``--body``). The commands call the public API as
a user's script does, through the package (``ph.simulate``).
"""

from __future__ import annotations

import os
import sys

from polhode.cli._common import UsageError
from polhode.cli._parser import build_parser

__all__ = ["main"]


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status: 0, 2 for bad arguments (with a message on
    stderr, never a traceback) or no command (the help on stdout, the error on stderr), 1 when
    writing an output fails, 130 on Ctrl-C, 141 (as a shell reports SIGPIPE) when the reader
    of the output goes away, as in ``polhode ... | head``."""
    try:
        return _main(argv)
    except BrokenPipeError:
        # Whatever is still buffered for the closed pipe goes nowhere, quietly, at exit too.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 141


def _main(argv: list[str] | None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    except SystemExit as stop:  # argparse: --help, --version, or a message and status 2
        return stop.code if isinstance(stop.code, int) else 0 if stop.code is None else 2
    if args.command is None:
        parser.print_help()
        print("polhode: error: no command given (`polhode demo` runs the demo)", file=sys.stderr)
        return 2
    try:
        result: int = args.run(args)
    except UsageError as error:
        print(f"polhode {args.command}: error: {error}", file=sys.stderr)
        return 2
    except (ValueError, TypeError) as error:  # PolhodeError is a ValueError
        print(f"polhode {args.command}: error: {error}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        raise  # main's: the reader went away, not an error of the output
    except OSError as error:
        print(f"polhode {args.command}: error: {error}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"polhode {args.command}: interrupted", file=sys.stderr)
        return 130
    return result
