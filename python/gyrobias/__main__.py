"""``python -m gyrobias``: the command line (same as the ``gyrobias`` script)."""

from gyrobias.cli import main

raise SystemExit(main())
