"""Allow ``python -m meshwright.cli``."""

import sys

from meshwright.cli import main

sys.exit(main())
