"""``python -m rocking.cli``: the same as the ``rocking`` command."""

from rocking.cli import main

raise SystemExit(main())
