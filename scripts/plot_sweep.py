#!/usr/bin/env python3
"""plot_sweep.py DIR [DIR ...] --output FIGDIR: the figures of one or more sweeps (swarm_forage.figures.sweep)."""
import sys

from swarm_forage.figures import sweep

if __name__ == '__main__':
    sys.exit(sweep.main())
