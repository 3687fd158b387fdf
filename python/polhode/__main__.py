"""``python -m polhode``: the command line (see ``polhode --help``)."""

from polhode.cli import main

raise SystemExit(main())
