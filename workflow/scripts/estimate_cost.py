#!/usr/bin/python3
"""Job count and estimated cost of a study config (granudrag_study.estimate; --help).

    /usr/bin/python3 workflow/scripts/estimate_cost.py config/paper.yaml [--by-sweep] [--measure]
"""

import sys

from granudrag_study.estimate import main

if __name__ == "__main__":
    sys.exit(main())
