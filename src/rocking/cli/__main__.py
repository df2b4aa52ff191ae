"""``python -m rocking.cli``: the same as the ``rocking`` command."""

from . import main

raise SystemExit(main())
