"""``python -m robomill``: the ``robomill`` command (:mod:`robomill.cli`)."""

from robomill.cli import main

raise SystemExit(main())
