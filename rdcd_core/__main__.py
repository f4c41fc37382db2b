import sys

from rdcd_core.cli import main

sys.exit(main())
