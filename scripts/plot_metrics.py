#!/usr/bin/env python3
"""plot_metrics.py DIR [--output FILE.png]: e(N), Z(N), R and A of the tables metrics/compute wrote
(swarm_forage.figures.metrics)."""
import sys

from swarm_forage.figures import metrics

if __name__ == '__main__':
    sys.exit(metrics.main())
