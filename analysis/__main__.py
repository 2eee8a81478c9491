"""`python -m analysis fit|report|predict` (analysis.cli)."""
import sys

from .cli import main

sys.exit(main())
