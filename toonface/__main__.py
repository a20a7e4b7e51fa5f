"""``python -m toonface`` runs the command line."""

import sys

from toonface.cli import main

sys.exit(main())
