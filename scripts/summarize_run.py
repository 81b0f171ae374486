#!/usr/bin/env python3
"""summarize_run.py BAG [--csv METRICS_CSV] [--plot OUT.png]: one run bag summarized (swarm_forage.bags.summary)."""
import sys

from swarm_forage.bags import summary

if __name__ == '__main__':
    sys.exit(summary.main())
